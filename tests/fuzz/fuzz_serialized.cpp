// Mitsuba .serialized meshes (volguide's own reader, zlib): shape 0, then shape 1 through the offset
// table at the end of the file.
#include "fuzz_input_file.h"
#include "fuzz_targets.h"
#include "volguide/core/error.h"
#include "volguide/geometry/shapes/mesh_files.h"

namespace volguide::fuzz {

int fuzz_serialized(const uint8_t* data, size_t size) {
    const std::string path = write_fuzz_input(data, size, ".serialized");
    for (int64_t index : {0, 1}) {
        try {
            (void)read_serialized(path, index, SourceLocation{"fuzz.xml", 1});
        } catch (const InputError&) {
            // The reader's contract for bad input: an error naming the file.
        }
    }
    return 0;
}

}  // namespace volguide::fuzz
