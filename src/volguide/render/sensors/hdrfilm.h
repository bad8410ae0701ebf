#pragma once
// Mitsuba 3's `hdrfilm`: resolution, reconstruction filter (default gaussian) and sample_border.
// volguide always writes linear float32 RGB (EXR) or an 8-bit sRGB preview (PNG), whatever the
// declared pixel/component/file format; cropping is not supported. Mitsuba 0.6's `ldrfilm` is the same
// film with its own PNG tonemap.
#include <cstdint>
#include <memory>

#include "volguide/core/properties.h"
#include "volguide/render/sensor.h"

namespace volguide {

std::shared_ptr<Film> make_hdrfilm(const Properties& props);
// Mitsuba 0.6's `ldrfilm` (read from 0.6 files; a volguide extension in 3.x ones): hdrfilm's resolution,
// filter and sample_border, and the tonemap volguide writes a PNG of the render with (render/tonemap.h):
// `tonemap_method` gamma (default: `exposure` in stops, then `gamma`, -1 the sRGB curve) or reinhard
// (`key` 0.18, `burn` 0, then `gamma`). An EXR is the linear image whatever the film.
std::shared_ptr<Film> make_ldrfilm(const Properties& props);

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
