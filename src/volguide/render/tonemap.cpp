#include "volguide/render/tonemap.h"

#include <algorithm>
#include <cmath>

#include "volguide/render/srgb.h"

namespace volguide {

namespace {

// Rec. 709 luminance, with the coefficients Mitsuba 0.6's tonemapper uses.
float luminance(const Color3& c) {
    return c.r * 0.212671f + c.g * 0.715160f + c.b * 0.072169f;
}

// Reinhard et al.'s global operator on luminance: the log-average luminance is scaled to `key` and
// L' = L (1 + L / Lw²) / (1 + L), where the white point Lw is the brightest pixel (made smaller by
// `burn`, as 0.6's burn / b⁴ knob). Chromaticity is kept: each pixel's RGB is scaled by L' / L.
Image reinhard(const Image& image, float key, float burn) {
    double log_sum = 0;
    size_t n = 0;
    float max_luminance = 0;
    for (const Color3& c : image.pixels) {
        const float l = luminance(c);
        if (!std::isfinite(l)) continue;
        max_luminance = std::max(max_luminance, l);
        log_sum += std::log(1e-3 + double(std::max(l, 0.f)));
        ++n;
    }
    if (!(max_luminance > 0)) return image;  // a black image stays black
    const float log_average = float(std::exp(log_sum / double(n)));
    const float b = std::clamp(1.f - burn, 1e-8f, 1.f);
    const float scale = key / log_average, white = max_luminance * scale;
    const float inv_white2 = 1.f / (white * white * std::pow(b, 4.f));
    Image out = image;
    for (Color3& c : out.pixels) {
        const float l = luminance(c);
        if (!(l > 0)) {
            c = Color3(0.f);
            continue;
        }
        const float lp = l * scale;
        c = c * (lp * (1.f + lp * inv_white2) / (1.f + lp) / l);
    }
    return out;
}

float encode(float v, float gamma) {
    v = std::isnan(v) ? 0.f : std::clamp(v, 0.f, 1.f);
    return gamma == -1.f ? linear_to_srgb(v) : std::pow(v, 1.f / gamma);
}

}  // namespace

Image display_values(const Image& linear, const PngTonemap& t) {
    Image out = t.method == PngTonemap::Method::reinhard ? reinhard(linear, t.key, t.burn) : linear;
    const float multiplier = t.method == PngTonemap::Method::gamma ? std::exp2(t.exposure) : 1.f;
    for (Color3& c : out.pixels)
        for (int i = 0; i < 3; ++i) c[i] = encode(c[i] * multiplier, t.gamma);
    return out;
}

}  // namespace volguide
