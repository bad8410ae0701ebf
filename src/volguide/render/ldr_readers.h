#pragma once
// Decoders of the 8- and 16-bit image formats textures use, each behind size checks made before it
// allocates: PNG through libpng, JPEG through libjpeg(-turbo), BMP and TGA through stb_image built
// for those two formats only. (stb_image's other decoders, and its PNG and JPEG ones, are not used:
// stb is not meant for untrusted files, and the fuzzer found its 2.27 JPEG decoder writing past a
// table, docs/reliability.md.) The sRGB curve is the caller's (image_io.cpp).
#include <cstdint>
#include <string>
#include <vector>

namespace volguide {

// RGB samples, row-major from the top row, 3 per pixel, in [0, max_value] (255 or 65535).
struct LdrPixels {
    int width = 0, height = 0;
    uint32_t max_value = 255;
    std::vector<uint16_t> samples;
};

// Each throws InputError naming the file for a malformed file, a size the file cannot hold, or
// buffers beyond the memory budget.
LdrPixels read_png_pixels(const std::string& path);
LdrPixels read_jpeg_pixels(const std::string& path);
LdrPixels read_bmp_tga_pixels(const std::string& path);

// The checks made before decoding: positive, no more pixels than a file of its size could describe
// (`max_pixels_per_byte`), and `bytes_per_pixel` of decode buffers within the memory budget.
void check_ldr_size(const std::string& path, uint64_t width, uint64_t height, uint64_t max_pixels_per_byte,
                    uint64_t bytes_per_pixel);

}  // namespace volguide
