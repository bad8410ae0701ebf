#pragma once
// The canonical text of an integrator's configuration: its plugin type and every parameter as the
// scene gave it (after -D substitution), sorted by name, nested integrators (moment) included, e.g.
// `guided_volpath{photons=20000, rrs="grrs"}`. Parameters that only name output files
// (`save_field`, `save_pixel_estimate`) are left out: they change no pixel. Two integrators with the
// same text render the same image from the same samples; `volguide train` stores it with the
// pre-pass and `render --field` / `merge` compare it (docs/distributed.md).
#include <string>

#include "volguide/core/properties.h"

namespace volguide {

std::string integrator_configuration(const Properties& props);

}  // namespace volguide
