// The XML scene loader through scene construction (plugins, meshes, media, accel), without rendering.
#include "fuzz_input_file.h"
#include "fuzz_targets.h"
#include "volguide/core/error.h"
#include "volguide/scene/loader.h"

namespace volguide::fuzz {

int fuzz_scene(const uint8_t* data, size_t size) {
    const std::string path = write_fuzz_input(data, size, ".xml");
    try {
        (void)load_scene(path);
    } catch (const InputError&) {
        // The reader's contract for bad input: an error naming the file.
    }
    return 0;
}

}  // namespace volguide::fuzz
