#pragma once
// The parameters `homogeneous` and `heterogeneous` share (Mitsuba 3 names and defaults):
// sigma_t (1), albedo (0.75), scale (1), sample_emitters (true), a nested phase (isotropic).
#include "volguide/core/properties.h"
#include "volguide/media/phase.h"
#include "volguide/media/volume.h"

namespace volguide {

struct MediumParams {
    std::shared_ptr<Volume> sigma_t, albedo;  // sigma_t without `scale`
    float scale = 1.f;
    bool sample_emitters = true;
    std::shared_ptr<PhaseFunction> phase;
};

// Validates: sigma_t >= 0, albedo in [0, 1], scale finite and >= 0, at most one phase child.
MediumParams read_medium_params(const Properties& props);

}  // namespace volguide
