// Mitsuba's binary .vol grids.
#include "fuzz_input_file.h"
#include "fuzz_targets.h"
#include "volguide/core/error.h"
#include "volguide/media/grid_data.h"

namespace volguide::fuzz {

int fuzz_vol(const uint8_t* data, size_t size) {
    const std::string path = write_fuzz_input(data, size, ".vol");
    try {
        (void)read_vol_file(path);
    } catch (const InputError&) {
        // The reader's contract for bad input: an error naming the file.
    }
    return 0;
}

}  // namespace volguide::fuzz
