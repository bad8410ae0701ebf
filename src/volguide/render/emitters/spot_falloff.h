#pragma once
// Mitsuba 3's spot light profile: 1 inside the beam (angle <= beam_width), falling linearly in the
// angle to 0 at cutoff_angle, 0 beyond.
#include <cmath>

#include "volguide/core/math.h"
#include "volguide/core/vec.h"

namespace volguide {

class SpotFalloff {
  public:
    SpotFalloff() = default;
    // Angles in degrees; requires 0 < beam_width <= cutoff_angle.
    SpotFalloff(float cutoff_deg, float beam_deg)
        : cutoff_(deg_to_rad(cutoff_deg)),
          inv_transition_width_(1.f / (deg_to_rad(cutoff_deg) - deg_to_rad(beam_deg))),
          cos_cutoff_(std::cos(deg_to_rad(cutoff_deg))),
          cos_beam_(std::cos(deg_to_rad(beam_deg))) {}

    // `local_dir`: emission direction in the light's frame (the beam points along +z); any length.
    float operator()(const Vec3f& local_dir) const {
        const float cos_theta = normalize(local_dir).z;
        if (!(cos_theta > cos_cutoff_)) return 0.f;
        if (cos_theta >= cos_beam_) return 1.f;
        return (cutoff_ - std::acos(cos_theta)) * inv_transition_width_;
    }

    float cos_cutoff() const { return cos_cutoff_; }

    // Integral of the profile over solid angle, 2 pi int_0^cutoff f(theta) sin(theta) dtheta:
    // 2 pi (1 - cos b) inside the beam b, plus 2 pi int_b^c (c - theta) / (c - b) sin(theta) dtheta
    // = 2 pi (cos b - (sin c - sin b) / (c - b)) on the linear ramp to the cutoff c.
    double solid_angle_integral() const {
        const double c = cutoff_, b = double(cutoff_) - 1.0 / double(inv_transition_width_);
        if (!(c - b > 1e-7)) return 2.0 * 3.14159265358979323846 * (1.0 - std::cos(c));  // no ramp
        return 2.0 * 3.14159265358979323846 * (1.0 - (std::sin(c) - std::sin(b)) / (c - b));
    }

  private:
    float cutoff_ = 0.f, inv_transition_width_ = 0.f, cos_cutoff_ = 1.f, cos_beam_ = 1.f;
};

}  // namespace volguide
