#pragma once
// A float RGB image, row-major, top row first.
#include <vector>

#include "volguide/core/color.h"

namespace volguide {

struct Image {
    int width = 0, height = 0;
    std::vector<Color3> pixels;
    Image() = default;
    Image(int w, int h, Color3 fill = Color3(0.f)) : width(w), height(h), pixels(size_t(w) * h, fill) {}
    Color3& at(int x, int y) { return pixels[size_t(y) * width + x]; }
    const Color3& at(int x, int y) const { return pixels[size_t(y) * width + x]; }
};

}  // namespace volguide
