// Texture images through read_image (render/ldr_readers.h): PNG through libpng (RGBA, gray, 16-bit,
// palette with and without transparency), JPEG through libjpeg (gray converted, a truncated file
// decoded with a warning naming it), BMP and TGA through stb's two decoders, other formats refused
// by name.
#include <gtest/gtest.h>
#include <png.h>
#include <stb/stb_image_write.h>

#include <cstdint>
#include <string>
#include <vector>

#include "support/cli.h"
#include "test_loader_util.h"
#include "volguide/core/error.h"
#include "volguide/core/log.h"
#include "volguide/render/image_io.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// Writes `pixels` (bytes or 16-bit samples, as `format` says) with libpng's simplified writer.
void write_png_format(const std::string& path, int width, int height, png_uint_32 format, const void* pixels,
                      const void* colormap = nullptr, int colormap_entries = 0) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = png_uint_32(width);
    image.height = png_uint_32(height);
    image.format = format;
    image.colormap_entries = png_uint_32(colormap_entries);
    ASSERT_TRUE(png_image_write_to_file(&image, path.c_str(), 0, pixels, 0, colormap)) << image.message;
}

}  // namespace

TEST(LdrReaders, PngColourTypesAndDepthsReadAsRgb) {
    ScratchDir dir;
    // RGBA: the alpha channel is dropped, not composited (as Mitsuba's bitmap and stb did).
    const uint8_t rgba[2 * 4] = {200, 100, 50, 10, 0, 255, 128, 255};
    write_png_format(dir.path("rgba.png"), 2, 1, PNG_FORMAT_RGBA, rgba);
    Image a = read_image(dir.path("rgba.png"), true);
    ASSERT_EQ(a.width, 2);
    EXPECT_FLOAT_EQ(a.pixels[0].r, 200 / 255.f);
    EXPECT_FLOAT_EQ(a.pixels[0].g, 100 / 255.f);
    EXPECT_FLOAT_EQ(a.pixels[0].b, 50 / 255.f);
    EXPECT_FLOAT_EQ(a.pixels[1].b, 128 / 255.f);

    const uint8_t gray[3] = {0, 77, 255};
    write_png_format(dir.path("gray.png"), 3, 1, PNG_FORMAT_GRAY, gray);
    Image g = read_image(dir.path("gray.png"), true);
    EXPECT_FLOAT_EQ(g.pixels[1].r, 77 / 255.f);
    EXPECT_FLOAT_EQ(g.pixels[1].b, 77 / 255.f);

    // 16-bit samples keep their precision (libpng's "linear" format writes 16 bits; the reader
    // ignores the file's gAMA, as Mitsuba does).
    const uint16_t deep[3] = {40000, 1, 65535};
    write_png_format(dir.path("deep.png"), 1, 1, PNG_FORMAT_LINEAR_RGB, deep);
    Image d = read_image(dir.path("deep.png"), true);
    EXPECT_FLOAT_EQ(d.pixels[0].r, 40000 / 65535.f);
    EXPECT_FLOAT_EQ(d.pixels[0].g, 1 / 65535.f);
    EXPECT_FLOAT_EQ(d.pixels[0].b, 1.f);

    // Palette: expanded through the colormap; the sRGB curve applies unless raw.
    const uint8_t colormap[2 * 3] = {10, 20, 30, 250, 240, 230};
    const uint8_t indices[4] = {1, 0, 0, 1};
    write_png_format(dir.path("palette.png"), 2, 2, PNG_FORMAT_RGB_COLORMAP, indices, colormap, 2);
    Image p = read_image(dir.path("palette.png"), true);
    EXPECT_FLOAT_EQ(p.pixels[0].g, 240 / 255.f);
    EXPECT_FLOAT_EQ(p.pixels[1].r, 10 / 255.f);
    Image srgb = read_image(dir.path("palette.png"));
    EXPECT_NEAR(srgb.pixels[0].g, 0.8713671f, 1e-5f);  // sRGB 240/255 in linear light

    // Palette with transparency (a tRNS chunk, as pngquant writes): its alpha is dropped too.
    const uint8_t colormap_alpha[2 * 4] = {10, 20, 30, 0, 250, 240, 230, 128};
    write_png_format(dir.path("palette_alpha.png"), 2, 2, PNG_FORMAT_RGBA_COLORMAP, indices, colormap_alpha,
                     2);
    Image pa = read_image(dir.path("palette_alpha.png"), true);
    EXPECT_FLOAT_EQ(pa.pixels[1].b, 30 / 255.f);
    EXPECT_FLOAT_EQ(pa.pixels[3].r, 250 / 255.f);
}

TEST(LdrReaders, JpegGrayIsConvertedAndATruncatedFileWarnsNamingIt) {
    ScratchDir dir;
    std::vector<uint8_t> gray(16 * 16, 128);
    ASSERT_TRUE(stbi_write_jpg(dir.path("gray.jpg").c_str(), 16, 16, 1, gray.data(), 95));
    Image g = read_image(dir.path("gray.jpg"), true);
    ASSERT_EQ(g.width, 16);
    EXPECT_NEAR(g.pixels[37].r, 128 / 255.f, 2 / 255.f);
    EXPECT_EQ(g.pixels[37].r, g.pixels[37].b);

    std::vector<uint8_t> rgb(64 * 64 * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = uint8_t(i * 7);
    ASSERT_TRUE(stbi_write_jpg(dir.path("full.jpg").c_str(), 64, 64, 3, rgb.data(), 90));
    const std::string full = read_file(dir.path("full.jpg"));
    const std::string cut = dir.write("cut.jpg", full.substr(0, full.size() / 2));
    std::vector<std::string> warnings;
    WarningHandler previous = set_warning_handler(
        [&](const SourceLocation& loc, const std::string& m) { warnings.push_back(loc.file + ": " + m); });
    Image c = read_image(cut);
    set_warning_handler(previous);
    EXPECT_EQ(c.width, 64);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("cut.jpg: JPEG with"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("Premature end of JPEG file"), std::string::npos) << warnings[0];
}

TEST(LdrReaders, BmpByContentTgaByExtensionOtherFormatsRefused) {
    ScratchDir dir;
    const uint8_t rgb[2 * 3] = {1, 2, 3, 250, 251, 252};
    ASSERT_TRUE(stbi_write_bmp(dir.path("a.bmp").c_str(), 2, 1, 3, rgb));
    ASSERT_TRUE(stbi_write_tga(dir.path("a.tga").c_str(), 2, 1, 3, rgb));
    for (const char* name : {"a.bmp", "a.tga"}) {
        Image im = read_image(dir.path(name), true);
        ASSERT_EQ(im.width, 2) << name;
        EXPECT_FLOAT_EQ(im.pixels[1].g, 251 / 255.f) << name;
    }
    // The same TGA bytes under another name have no signature to be known by.
    const std::string renamed = dir.write("a.img", read_file(dir.path("a.tga")));
    const std::string gif = dir.write("a.gif", std::string("GIF89a\x01\x00\x01\x00\x00\x00\x00;", 14));
    for (const std::string& path : {renamed, gif}) {
        try {
            read_image(path);
            ADD_FAILURE() << path << " accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(
                          path + ": unsupported image format: volguide reads OpenEXR, PNG, JPEG"),
                      std::string::npos)
                << e.what();
        }
    }
}

// An 8-bit BMP whose pixels index past the two palette entries it holds: stb 2.27 reads those
// entries of its palette table uninitialised (nothings/stb#1929); volguide compiles stb with zeroed
// automatic variables, so they read black, the same on every run.
TEST(LdrReaders, BmpIndicesPastThePaletteReadBlack) {
    ScratchDir dir;
    // 14-byte file header, 40-byte info header, 2 palette entries (BGRA), one row of 4 indices.
    std::string bmp = "BM";
    auto u32 = [&](uint32_t v) { bmp.append(reinterpret_cast<const char*>(&v), 4); };
    auto u16 = [&](uint16_t v) { bmp.append(reinterpret_cast<const char*>(&v), 2); };
    u32(14 + 40 + 8 + 4);
    u32(0);
    u32(14 + 40 + 8);  // pixel data offset: the palette holds (62 - 54) / 4 = 2 entries
    u32(40);
    u32(4);  // width
    u32(1);  // height
    u16(1);
    u16(8);                              // bits per pixel
    for (int i = 0; i < 6; ++i) u32(0);  // compression, image size, resolution, colours used / important
    bmp += std::string("\x10\x20\x30\x00\x40\x50\x60\x00", 8);
    bmp += std::string("\x01\xc8\x00\xff", 4);  // indices 1, 200, 0, 255
    const std::string path = dir.write("short_palette.bmp", bmp);
    Image im = read_image(path, true);
    ASSERT_EQ(im.width, 4);
    EXPECT_FLOAT_EQ(im.pixels[0].r, 0x60 / 255.f);
    EXPECT_FLOAT_EQ(im.pixels[2].b, 0x10 / 255.f);
    for (int i : {1, 3}) {
        EXPECT_EQ(im.pixels[i].r, 0.f) << i;
        EXPECT_EQ(im.pixels[i].g, 0.f) << i;
        EXPECT_EQ(im.pixels[i].b, 0.f) << i;
    }
}
