// Stanford PLY meshes (volguide's own reader).
#include "fuzz_input_file.h"
#include "fuzz_targets.h"
#include "volguide/core/error.h"
#include "volguide/geometry/shapes/mesh_files.h"

namespace volguide::fuzz {

int fuzz_ply(const uint8_t* data, size_t size) {
    const std::string path = write_fuzz_input(data, size, ".ply");
    try {
        (void)read_ply(path, SourceLocation{"fuzz.xml", 1});
    } catch (const InputError&) {
        // The reader's contract for bad input: an error naming the file.
    }
    return 0;
}

}  // namespace volguide::fuzz
