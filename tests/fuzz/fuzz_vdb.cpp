// OpenVDB files as `gridvolume` reads them (grid "density", densified).
#include "fuzz_input_file.h"
#include "fuzz_targets.h"
#include "volguide/core/error.h"
#include "volguide/media/grid_data.h"

namespace volguide::fuzz {

int fuzz_vdb(const uint8_t* data, size_t size) {
    const std::string path = write_fuzz_input(data, size, ".vdb");
    try {
        (void)read_vdb_file(path, "density");
    } catch (const InputError&) {
        // The reader's contract for bad input: an error naming the file.
    }
    return 0;
}

}  // namespace volguide::fuzz
