#pragma once
// Mitsuba 3's `hdrfilm`: resolution, reconstruction filter (default gaussian) and sample_border.
// volguide always writes linear float32 RGB (EXR) or an 8-bit sRGB preview (PNG), whatever the
// declared pixel/component/file format; cropping is not supported.
#include <cstdint>
#include <memory>

#include "volguide/core/properties.h"
#include "volguide/render/sensor.h"

namespace volguide {

std::shared_ptr<Film> make_hdrfilm(const Properties& props);

// Memory a render of a width x height film needs for its pixels: the accumulators in double (sum of
// w L, of w L^2 and of w), the result images (mean, variance, weight) and the EXR's channels, about
// 128 bytes a pixel. hdrfilm rejects a film needing more than the machine's physical memory.
inline constexpr uint64_t kFilmBytesPerPixel = 128;
inline uint64_t film_memory_bytes(int64_t width, int64_t height) {
    return uint64_t(width) * uint64_t(height) * kFilmBytesPerPixel;
}
// Mitsuba's default film (768 x 576, gaussian filter), for a sensor without <film>.
std::shared_ptr<Film> make_default_film();

}  // namespace volguide
