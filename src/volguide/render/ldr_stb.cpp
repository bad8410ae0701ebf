// BMP and TGA through stb_image, compiled here from Debian's header for those two formats only
// (STBI_ONLY_*), with private (static) symbols, so none of stb's other decoders is reachable from a
// file and Debian's libstb (which volguide links for stb_image_write) is not used for reading. This
// file is kept out of unity batches: its static stb functions must not meet the library's
// declarations of libstb's.
#include "volguide/render/ldr_readers.h"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_BMP
#define STBI_ONLY_TGA
#define STBI_NO_HDR
#define STBI_NO_LINEAR
#define STBI_FAILURE_USERMSG
// Zeroed allocations: stb 2.27 returns a truncated uncompressed TGA's missing pixels from its
// buffer as they were (CVE-2023-45663); zeroed, they are black and the same on every run.
#define STBI_MALLOC(size) std::calloc(1, size)
#define STBI_REALLOC(p, size) std::realloc(p, size)
#define STBI_FREE(p) std::free(p)
#include <cstdlib>
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

#include <algorithm>
#include <memory>

#include "volguide/core/error.h"

namespace volguide {

LdrPixels read_bmp_tga_pixels(const std::string& path) {
    int w = 0, h = 0, n = 0;
    if (!stbi_info(path.c_str(), &w, &h, &n))
        fail_file(path, std::string("cannot read image: ") + stbi_failure_reason());
    // An uncompressed 1-bit BMP holds 8 pixels a byte; a TGA run of 128 pixels takes 2 bytes or more.
    check_ldr_size(path, uint64_t(std::max(w, 0)), uint64_t(std::max(h, 0)), 128, 2 * 4 + 3 * 2 + 12);
    int w2 = 0, h2 = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> data(stbi_load(path.c_str(), &w2, &h2, &n, 3), stbi_image_free);
    if (!data) fail_file(path, std::string("cannot read image: ") + stbi_failure_reason());
    if (w2 != w || h2 != h) fail_file(path, "cannot read image: its size changed between two reads");
    LdrPixels out;
    out.width = w2;
    out.height = h2;
    out.max_value = 255;
    out.samples.assign(data.get(), data.get() + size_t(w) * h * 3);
    return out;
}

}  // namespace volguide
