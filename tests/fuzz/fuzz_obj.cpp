// Wavefront OBJ meshes (tinyobjloader plus the fan triangulation and vertex sharing).
#include "fuzz_input_file.h"
#include "fuzz_targets.h"
#include "volguide/core/error.h"
#include "volguide/geometry/shapes/mesh_files.h"

namespace volguide::fuzz {

int fuzz_obj(const uint8_t* data, size_t size) {
    const std::string path = write_fuzz_input(data, size, ".obj");
    try {
        (void)read_obj(path, false, SourceLocation{"fuzz.xml", 1});
    } catch (const InputError&) {
        // The reader's contract for bad input: an error naming the file.
    }
    return 0;
}

}  // namespace volguide::fuzz
