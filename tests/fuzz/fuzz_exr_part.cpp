// EXR parts of a render: channels and the volguide.* header attributes `volguide merge` reads.
#include "fuzz_input_file.h"
#include "fuzz_targets.h"
#include "volguide/core/error.h"
#include "volguide/render/render_part.h"

namespace volguide::fuzz {

int fuzz_exr_part(const uint8_t* data, size_t size) {
    const std::string path = write_fuzz_input(data, size, ".exr");
    try {
        (void)read_part(path);
    } catch (const InputError&) {
        // The reader's contract for bad input: an error naming the file.
    }
    return 0;
}

}  // namespace volguide::fuzz
