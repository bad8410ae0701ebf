#pragma once
// Reading and writing images. Writers are atomic: they write a temporary file next to the target
// and rename it, so an interrupted or failed write never leaves a corrupt or partial image.
#include <string>

#include "volguide/core/image.h"
#include "volguide/render/tonemap.h"

namespace volguide {

// EXR (any RGB/Y float or half channels), and PNG, JPEG, BMP and TGA (8- or 16-bit sRGB, converted
// to linear unless `raw` is set, e.g. for data textures; render/ldr_readers.h). Throws InputError
// naming the file on any failure, an unsupported format included.
Image read_image(const std::string& path, bool raw = false);
// Linear float32 RGB EXR.
void write_exr(const std::string& path, const Image& image);
// 8-bit PNG: by default the sRGB preview (clamped, gamma encoded); a film's tonemap otherwise.
void write_png(const std::string& path, const Image& image, const PngTonemap& tonemap = {});
// Dispatches on the extension (.exr or .png, written with `tonemap`); throws InputError for anything else.
void write_image(const std::string& path, const Image& image, const PngTonemap& tonemap = {});

}  // namespace volguide
