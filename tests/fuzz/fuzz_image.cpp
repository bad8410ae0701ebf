// Images as a `bitmap` texture or an `envmap` reads them (read_image): EXR through OpenEXR behind
// volguide's header checks; PNG (libpng), JPEG (libjpeg), BMP and TGA (stb_image's two decoders)
// behind the size checks of render/ldr_readers.h.
#include "fuzz_input_file.h"
#include "fuzz_targets.h"
#include "volguide/core/error.h"
#include "volguide/render/image_io.h"

namespace volguide::fuzz {

int fuzz_image(const uint8_t* data, size_t size) {
    // Once by signature (EXR, PNG, JPEG, BMP; anything else is refused) and once as a .tga, the
    // format known by its extension.
    for (const char* extension : {".img", ".tga"}) {
        const std::string path = write_fuzz_input(data, size, extension);
        try {
            (void)read_image(path);
        } catch (const InputError&) {
            // The reader's contract for bad input: an error naming the file.
        }
    }
    return 0;
}

}  // namespace volguide::fuzz
