// Bitmap lookups (no file I/O here: see bitmap_plugin.cpp).
#include <cmath>

#include "volguide/render/textures/textures.h"

namespace volguide {

BitmapTexture::BitmapTexture(Image image, BitmapFilter filter, BitmapWrap wrap, UvTransform to_uv)
    : image_(std::move(image)), filter_(filter), wrap_(wrap), to_uv_(to_uv) {
    double sum = 0.0;
    for (const Color3& c : image_.pixels) sum += double(c.luminance());
    mean_ = image_.pixels.empty() ? 0.f : float(sum / double(image_.pixels.size()));
}

int BitmapTexture::wrap(int value, int res) const {
    if (wrap_ == BitmapWrap::Clamp) return std::clamp(value, 0, res - 1);
    const int div = value / res;  // truncates towards zero, as Mitsuba's integer divisor
    int mod = value - div * res;
    if (mod < 0) mod += res;
    if (wrap_ == BitmapWrap::Mirror && !(((div & 1) == 0) != (value < 0))) mod = res - 1 - mod;
    return mod;
}

Color3 BitmapTexture::lookup(Vec2f uv) const {
    const int w = image_.width, h = image_.height;
    if (filter_ == BitmapFilter::Nearest) {
        const int x = int(std::floor(uv.x * float(w))), y = int(std::floor(uv.y * float(h)));
        return image_.at(wrap(x, w), wrap(y, h));
    }
    // Bilinear between pixel centres.
    const float px = uv.x * float(w) - 0.5f, py = uv.y * float(h) - 0.5f;
    const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
    const float w1x = px - float(x0), w1y = py - float(y0), w0x = 1.f - w1x, w0y = 1.f - w1y;
    const int xa = wrap(x0, w), xb = wrap(x0 + 1, w), ya = wrap(y0, h), yb = wrap(y0 + 1, h);
    const Color3 v0 = image_.at(xa, ya) * w0x + image_.at(xb, ya) * w1x;
    const Color3 v1 = image_.at(xa, yb) * w0x + image_.at(xb, yb) * w1x;
    return v0 * w0y + v1 * w1y;
}

Vec2f BitmapTexture::eval_1_grad(const SurfaceInteraction& si) const {
    if (filter_ == BitmapFilter::Nearest) return Vec2f(0.f, 0.f);
    const int w = image_.width, h = image_.height;
    const Vec2f uv = to_uv_.apply(si.uv);
    const float px = uv.x * float(w) - 0.5f, py = uv.y * float(h) - 0.5f;
    const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
    const float w1x = px - float(x0), w1y = py - float(y0), w0x = 1.f - w1x, w0y = 1.f - w1y;
    const int xa = wrap(x0, w), xb = wrap(x0 + 1, w), ya = wrap(y0, h), yb = wrap(y0 + 1, h);
    const float f00 = image_.at(xa, ya).luminance(), f10 = image_.at(xb, ya).luminance();
    const float f01 = image_.at(xa, yb).luminance(), f11 = image_.at(xb, yb).luminance();
    const float dx = w0y * (f10 - f00) + w1y * (f11 - f01), dy = w0x * (f01 - f00) + w1x * (f11 - f10);
    const float du = to_uv_.m[0][0] * dx + to_uv_.m[1][0] * dy, dv = to_uv_.m[0][1] * dx + to_uv_.m[1][1] * dy;
    return Vec2f(du * float(w), dv * float(h));
}

Color3 BitmapTexture::eval(const SurfaceInteraction& si) const {
    return lookup(to_uv_.apply(si.uv));
}

}  // namespace volguide
