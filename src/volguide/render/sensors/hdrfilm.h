#pragma once
// Mitsuba 3's `hdrfilm`: resolution, reconstruction filter (default gaussian) and sample_border.
// volguide always writes linear float32 RGB (EXR) or an 8-bit sRGB preview (PNG), whatever the
// declared pixel/component/file format; cropping is not supported.
#include <memory>

#include "volguide/core/properties.h"
#include "volguide/render/sensor.h"

namespace volguide {

std::shared_ptr<Film> make_hdrfilm(const Properties& props);
// Mitsuba's default film (768 x 576, gaussian filter), for a sensor without <film>.
std::shared_ptr<Film> make_default_film();

}  // namespace volguide
