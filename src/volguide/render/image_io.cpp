// Image reading/writing: EXR via OpenEXR 3; PNG, JPEG, BMP and TGA through ldr_readers.h; PNG
// output through stb_image_write (compiled into Debian's libstb, so not instantiated here).
#include "volguide/render/image_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <stb/stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>

#include "volguide/core/atomic_write.h"
#include "volguide/core/error.h"
#include "volguide/render/exr_header_check.h"
#include "volguide/render/ldr_readers.h"
#include "volguide/render/srgb.h"

namespace volguide {
namespace {

std::string lower_extension(const std::string& path) {
    const size_t dot = path.find_last_of('.');
    const size_t slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
    std::string ext = path.substr(dot);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

enum class ImageFormat { exr, png, jpeg, bmp, tga, unknown };

// By signature (EXR, PNG, JPEG, BMP); TGA has none, so by its extension.
ImageFormat image_format(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail_file(path, "cannot open image file");
    unsigned char m[8] = {};
    in.read(reinterpret_cast<char*>(m), 8);
    const std::streamsize n = in.gcount();
    static const unsigned char exr[4] = {0x76, 0x2f, 0x31, 0x01};
    static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (n >= 4 && std::equal(m, m + 4, exr)) return ImageFormat::exr;
    if (n == 8 && std::equal(m, m + 8, png)) return ImageFormat::png;
    if (n >= 3 && m[0] == 0xff && m[1] == 0xd8 && m[2] == 0xff) return ImageFormat::jpeg;
    if (n >= 2 && m[0] == 'B' && m[1] == 'M') return ImageFormat::bmp;
    return lower_extension(path) == ".tga" ? ImageFormat::tga : ImageFormat::unknown;
}

Image read_exr(const std::string& path) {
    check_exr_header(path);
    try {
        Imf::InputFile file(path.c_str());
        const Imf::Header& header = file.header();
        const Imath::Box2i dw = header.dataWindow();
        const ExrSize size = checked_exr_size(path, dw.min.x, dw.min.y, dw.max.x, dw.max.y, 3);
        const int w = size.width, h = size.height;
        const Imf::ChannelList& channels = header.channels();
        const bool rgb = channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B");
        const bool gray = !rgb && channels.findChannel("Y");
        if (!rgb && !gray) fail_file(path, "EXR image has neither R, G, B nor Y channels");

        Image image(w, h);
        // Slices are read as float whatever the stored type (OpenEXR converts half).
        Imf::FrameBuffer fb;
        char* base = reinterpret_cast<char*>(image.pixels.data());
        const size_t xs = sizeof(Color3), ys = sizeof(Color3) * size_t(w);
        auto slice = [&](const char* name, int offset) {
            fb.insert(name, Imf::Slice::Make(Imf::FLOAT, base + offset, dw, xs, ys));
        };
        if (rgb) {
            slice("R", offsetof(Color3, r));
            slice("G", offsetof(Color3, g));
            slice("B", offsetof(Color3, b));
        } else {
            slice("Y", offsetof(Color3, r));
        }
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        if (gray)
            for (Color3& c : image.pixels) c = Color3(c.r);
        return image;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        fail_file(path, std::string("cannot read EXR image: ") + e.what());
    }
}

// 8- or 16-bit samples as linear floats (sRGB decoded unless raw).
Image to_image(const LdrPixels& p, bool raw) {
    Image image(p.width, p.height);
    auto convert = [&](float v) { return raw ? v : srgb_to_linear(v); };
    float* out = &image.pixels[0].r;
    if (p.max_value == 255) {
        std::array<float, 256> table;
        for (int i = 0; i < 256; ++i) table[i] = convert(i / 255.f);
        for (size_t i = 0; i < p.samples.size(); ++i) out[i] = table[p.samples[i]];
    } else {
        // 16-bit PNGs keep their precision.
        for (size_t i = 0; i < p.samples.size(); ++i) out[i] = convert(p.samples[i] / 65535.f);
    }
    return image;
}

void write_image_atomically(const std::string& path, const std::function<void(const std::string&)>& write) {
    const std::string error = write_atomically(path, write);
    if (!error.empty()) fail_file(path, "cannot write image: " + error);
}

void check_image(const std::string& path, const Image& image) {
    if (image.width <= 0 || image.height <= 0 || image.pixels.size() != size_t(image.width) * image.height)
        fail_file(path, "cannot write an empty or inconsistent image");
}

}  // namespace

Image read_image(const std::string& path, bool raw) {
    switch (image_format(path)) {
        case ImageFormat::exr:
            return read_exr(path);
        case ImageFormat::png:
            return to_image(read_png_pixels(path), raw);
        case ImageFormat::jpeg:
            return to_image(read_jpeg_pixels(path), raw);
        case ImageFormat::bmp:
        case ImageFormat::tga:
            return to_image(read_bmp_tga_pixels(path), raw);
        case ImageFormat::unknown:
            break;
    }
    fail_file(path, "unsupported image format: volguide reads OpenEXR, PNG, JPEG, BMP and TGA (.tga)");
}

void write_exr(const std::string& path, const Image& image) {
    check_image(path, image);
    write_image_atomically(path, [&](const std::string& tmp) {
        Imf::Header header(image.width, image.height);
        header.channels().insert("R", Imf::Channel(Imf::FLOAT));
        header.channels().insert("G", Imf::Channel(Imf::FLOAT));
        header.channels().insert("B", Imf::Channel(Imf::FLOAT));
        Imf::OutputFile file(tmp.c_str(), header);
        char* base = const_cast<char*>(reinterpret_cast<const char*>(image.pixels.data()));
        const size_t xs = sizeof(Color3), ys = sizeof(Color3) * size_t(image.width);
        Imf::FrameBuffer fb;
        fb.insert("R", Imf::Slice(Imf::FLOAT, base + offsetof(Color3, r), xs, ys));
        fb.insert("G", Imf::Slice(Imf::FLOAT, base + offsetof(Color3, g), xs, ys));
        fb.insert("B", Imf::Slice(Imf::FLOAT, base + offsetof(Color3, b), xs, ys));
        file.setFrameBuffer(fb);
        file.writePixels(image.height);
    });
}

void write_png(const std::string& path, const Image& image, const PngTonemap& tonemap) {
    check_image(path, image);
    const Image display = display_values(image, tonemap);
    std::vector<unsigned char> bytes(image.pixels.size() * 3);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            bytes[3 * i + c] = static_cast<unsigned char>(std::lround(display.pixels[i][c] * 255.f));
    // Encoded in memory and written here: stbi_write_png ignores fwrite's errors, so a full disk left
    // a truncated PNG in place and the render reported success.
    std::string png;
    const auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
    };
    if (!stbi_write_png_to_func(append, &png, image.width, image.height, 3, bytes.data(), image.width * 3))
        fail_file(path, "cannot write image: PNG encoder failed");
    write_image_atomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out.write(png.data(), std::streamsize(png.size()));
        out.close();
        if (!out) throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
    });
}

void write_image(const std::string& path, const Image& image, const PngTonemap& tonemap) {
    const std::string ext = lower_extension(path);
    if (ext == ".exr")
        write_exr(path, image);
    else if (ext == ".png")
        write_png(path, image, tonemap);
    else
        fail_file(path, "unsupported output image format '" + ext + "' (use .exr or .png)");
}

}  // namespace volguide
