#pragma once
// How a linear image becomes the 8-bit values of a PNG. volguide's default is its preview: the sRGB
// curve, clamped. Mitsuba 0.6's ldrfilm (render/sensors/hdrfilm.h, make_ldrfilm) sets its own: an
// exposure and a gamma curve, or Reinhard et al.'s photographic operator (2002) then the curve.
#include "volguide/core/image.h"

namespace volguide {

struct PngTonemap {
    enum class Method { gamma, reinhard };
    Method method = Method::gamma;
    float gamma = -1.f;     // the display curve: -1 is sRGB's, else v^(1/gamma)
    float exposure = 0.f;   // gamma method: values scaled by 2^exposure first
    float key = 0.18f;      // reinhard: the image's log-average luminance is mapped to `key`
    float burn = 0.f;       // reinhard: in [0, 1], how far the brightest pixel may burn out (0: not at all)
};

// The display values, in [0, 1], of every pixel channel (NaN reads as 0): what is quantised to 8 bits.
Image display_values(const Image& linear, const PngTonemap& tonemap);

}  // namespace volguide
