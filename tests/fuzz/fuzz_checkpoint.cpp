// Render checkpoints (`volguide render --resume FILE`, integrators/checkpoint_file.h): the file's
// container and the render state in it. The integrator's own state inside is opaque bytes here.
#include "fuzz_input_file.h"
#include "fuzz_targets.h"
#include "volguide/integrators/checkpoint_file.h"

namespace volguide::fuzz {

int fuzz_checkpoint(const uint8_t* data, size_t size) {
    const std::string path = write_fuzz_input(data, size, ".ckpt");
    try {
        (void)load_checkpoint(path);
    } catch (const CheckpointError&) {
        // The reader's contract for bad input: an error saying what is wrong (the CLI names the file).
    }
    return 0;
}

}  // namespace volguide::fuzz
