#include "volguide/render/ldr_readers.h"

#include <fmt/format.h>
#include <jpeglib.h>
#include <png.h>

#include <algorithm>
#include <bit>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "volguide/core/error.h"
#include "volguide/core/log.h"
#include "volguide/core/memory.h"

namespace volguide {

void check_ldr_size(const std::string& path, uint64_t width, uint64_t height, uint64_t max_pixels_per_byte,
                    uint64_t bytes_per_pixel) {
    if (width == 0 || height == 0 || width > (1u << 24) || height > (1u << 24))
        fail_file(path, fmt::format("image of {} x {} pixels", width, height));
    std::error_code ec;
    const uint64_t file_size = std::filesystem::file_size(path, ec);
    const uint64_t pixels = width * height;
    if (ec || pixels > file_size * max_pixels_per_byte)
        fail_file(path,
                  fmt::format("a {} x {} image cannot fit in a file of {} bytes", width, height, file_size));
    const uint64_t bytes = pixels * bytes_per_pixel;
    const uint64_t have = memory_budget_bytes();
    if (have > 0 && bytes > have)
        fail_file(path, fmt::format("a {} x {} image needs {}, more than {}", width, height,
                                    format_bytes(bytes), memory_budget_description()));
}

namespace {

// Bytes a pixel may take while decoding: libpng's rows (16-bit RGBA before the transforms),
// libjpeg's whole-image coefficient buffers of a progressive file, the samples kept, and the float
// image the caller makes of them.
constexpr uint64_t kDecodeBytesPerPixel = 8 + 3 * 2 + 3 * 2 + 12;

// ---- PNG (libpng) ----

struct PngHandles {
    png_structp png = nullptr;
    png_infop info = nullptr;
    FILE* file = nullptr;
    std::string error;
    ~PngHandles() {
        if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
        if (file) std::fclose(file);
    }
};

void on_png_error(png_structp png, png_const_charp message) {
    static_cast<PngHandles*>(png_get_error_ptr(png))->error = message;
    png_longjmp(png, 1);
}

// Warnings (an sRGB profile libpng calls incorrect, a bad ancillary chunk) leave the pixels as
// the file has them.
void on_png_warning(png_structp, png_const_charp) {}

// libpng reports errors by longjmp to the setjmp here: nothing in this frame has a destructor, and
// everything it fills lives in the caller's frame.
bool decode_png(PngHandles* h, const std::string* path, std::vector<png_byte>* bytes,
                std::vector<png_bytep>* rows, LdrPixels* out) {
    if (setjmp(png_jmpbuf(h->png))) return false;
    png_init_io(h->png, h->file);
    // Ancillary chunks (ICC profiles, compressed text) are bounded at 8 MB each.
    png_set_chunk_malloc_max(h->png, 8u << 20);
    png_read_info(h->png, h->info);
    const png_uint_32 width = png_get_image_width(h->png, h->info);
    const png_uint_32 height = png_get_image_height(h->png, h->info);
    const int depth = png_get_bit_depth(h->png, h->info);
    const int color = png_get_color_type(h->png, h->info);
    // A 1-bit image at deflate's best ratio (1032:1) is the most pixels a byte can hold.
    check_ldr_size(*path, width, height, 8 * 1032, kDecodeBytesPerPixel);
    if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(h->png);
    if (color == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(h->png);
    // Alpha is dropped: an alpha channel, and the transparency (tRNS) palette_to_rgb expands.
    png_set_strip_alpha(h->png);
    if (color == PNG_COLOR_TYPE_GRAY || color == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(h->png);
    // PNG stores 16-bit samples big-endian; the uint16 samples are in host order.
    if (depth == 16 && std::endian::native == std::endian::little) png_set_swap(h->png);
    png_set_interlace_handling(h->png);
    png_read_update_info(h->png, h->info);
    const size_t sample_bytes = depth == 16 ? 2 : 1;
    const size_t row_bytes = size_t(width) * 3 * sample_bytes;
    if (png_get_rowbytes(h->png, h->info) != row_bytes) {
        h->error = "unexpected row size after conversion to RGB";
        return false;
    }
    bytes->resize(row_bytes * height);
    rows->resize(height);
    for (png_uint_32 y = 0; y < height; ++y) (*rows)[y] = bytes->data() + y * row_bytes;
    png_read_image(h->png, rows->data());
    png_read_end(h->png, nullptr);
    out->width = int(width);
    out->height = int(height);
    out->max_value = depth == 16 ? 65535 : 255;
    return true;
}

// ---- JPEG (libjpeg) ----

struct JpegError {
    jpeg_error_mgr manager;  // first: libjpeg's err pointer is cast back to JpegError
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX] = {};
    char first_warning[JMSG_LENGTH_MAX] = {};
};

struct JpegHandles {
    jpeg_decompress_struct info = {};
    JpegError error;
    jpeg_progress_mgr progress = {};
    FILE* file = nullptr;
    bool created = false;
    ~JpegHandles() {
        if (created) jpeg_destroy_decompress(&info);
        if (file) std::fclose(file);
    }
};

void on_jpeg_error(j_common_ptr info) {
    auto* e = reinterpret_cast<JpegError*>(info->err);
    (*info->err->format_message)(info, e->message);
    std::longjmp(e->jump, 1);
}

// Warnings (corrupt data, a file that ends early) are counted and the first kept for the caller.
void on_jpeg_message(j_common_ptr info, int level) {
    auto* e = reinterpret_cast<JpegError*>(info->err);
    if (level >= 0) return;  // trace messages
    if (e->manager.num_warnings++ == 0) (*info->err->format_message)(info, e->first_warning);
}

// A progressive file may hold any number of scans, each a pass over the whole image: a small file
// of many empty scans takes minutes. Real progressive files have about ten.
constexpr int kMaxJpegScans = 100;

void on_jpeg_progress(j_common_ptr common) {
    auto* info = reinterpret_cast<j_decompress_ptr>(common);
    if (info->is_decompressor && info->input_scan_number > kMaxJpegScans) {
        auto* e = reinterpret_cast<JpegError*>(info->err);
        std::snprintf(e->message, sizeof e->message, "more than %d progressive scans", kMaxJpegScans);
        std::longjmp(e->jump, 1);
    }
}

// libjpeg reports errors by longjmp to the setjmp here (as decode_png).
bool decode_jpeg(JpegHandles* h, const std::string* path, std::vector<unsigned char>* bytes, LdrPixels* out) {
    if (setjmp(h->error.jump)) return false;
    jpeg_create_decompress(&h->info);
    h->created = true;
    h->progress.progress_monitor = on_jpeg_progress;
    h->info.progress = &h->progress;
    h->info.mem->max_memory_to_use = long(std::min<uint64_t>(memory_budget_bytes(), uint64_t(1) << 40));
    jpeg_stdio_src(&h->info, h->file);
    jpeg_read_header(&h->info, TRUE);
    // A Huffman-coded baseline JPEG spends at least 2 bits on each 8 x 8 block of a component (its
    // DC and end-of-block codes): 256 pixels a byte at most; a progressive one at least 1 (a DC
    // scan of successive approximation): 512. Arithmetic coding has no such floor: only the
    // memory budget and the scan cap bound its work.
    const uint64_t max_pixels_per_byte =
        h->info.arith_code ? uint64_t(1) << 40 : (h->info.progressive_mode ? 512 : 256);
    check_ldr_size(*path, h->info.image_width, h->info.image_height, max_pixels_per_byte,
                   kDecodeBytesPerPixel);
    h->info.out_color_space = JCS_RGB;  // gray and YCbCr converted; CMYK is refused by libjpeg
    jpeg_start_decompress(&h->info);
    const size_t width = h->info.output_width, height = h->info.output_height;
    if (h->info.output_components != 3) {
        std::snprintf(h->error.message, sizeof h->error.message, "%d components after conversion to RGB",
                      h->info.output_components);
        return false;
    }
    bytes->resize(width * height * 3);
    while (h->info.output_scanline < height) {
        JSAMPROW row = bytes->data() + size_t(h->info.output_scanline) * width * 3;
        jpeg_read_scanlines(&h->info, &row, 1);
    }
    jpeg_finish_decompress(&h->info);
    out->width = int(width);
    out->height = int(height);
    out->max_value = 255;
    return true;
}

template <typename T>
void widen(const std::vector<T>& in, LdrPixels& out) {
    out.samples.assign(in.begin(), in.end());
}

}  // namespace

LdrPixels read_png_pixels(const std::string& path) {
    PngHandles h;
    h.file = std::fopen(path.c_str(), "rb");
    if (!h.file) fail_file(path, "cannot open image file");
    h.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &h, on_png_error, on_png_warning);
    if (!h.png) fail_file(path, "cannot read PNG: libpng could not start");
    h.info = png_create_info_struct(h.png);
    if (!h.info) fail_file(path, "cannot read PNG: libpng could not start");
    std::vector<png_byte> bytes;
    std::vector<png_bytep> rows;
    LdrPixels out;
    if (!decode_png(&h, &path, &bytes, &rows, &out)) fail_file(path, "cannot read PNG: " + h.error);
    if (out.max_value == 65535) {
        out.samples.resize(bytes.size() / 2);
        std::memcpy(out.samples.data(), bytes.data(), out.samples.size() * 2);
    } else {
        widen(bytes, out);
    }
    return out;
}

LdrPixels read_jpeg_pixels(const std::string& path) {
    JpegHandles h;
    h.file = std::fopen(path.c_str(), "rb");
    if (!h.file) fail_file(path, "cannot open image file");
    h.info.err = jpeg_std_error(&h.error.manager);
    h.error.manager.error_exit = on_jpeg_error;
    h.error.manager.emit_message = on_jpeg_message;
    std::vector<unsigned char> bytes;
    LdrPixels out;
    if (!decode_jpeg(&h, &path, &bytes, &out))
        fail_file(path, std::string("cannot read JPEG: ") + h.error.message);
    if (h.error.manager.num_warnings > 0)
        warn(SourceLocation{path, 0}, "JPEG with {} warning(s), decoded as libjpeg does (as Mitsuba): {}",
             h.error.manager.num_warnings, h.error.first_warning);
    widen(bytes, out);
    return out;
}

}  // namespace volguide
