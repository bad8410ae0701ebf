#include "volguide/integrators/volpath/equiangular.h"

#include <cmath>

#include "volguide/core/math.h"

namespace volguide {

EquiangularSampler::EquiangularSampler(const Point3f& o, const Vec3f& d, float tmax, const Point3f& c) {
    const Vec3f oc = c - o;
    delta_ = dot(oc, d);
    dist_ = norm(oc - d * delta_);
    tmax_ = tmax;
    // Relative threshold: below it tan() loses all precision and the density is a near-delta.
    valid_ = dist_ > 1e-5f * std::max(1.f, norm(oc)) && tmax > 0.f;
    if (!valid_) return;
    theta_a_ = std::atan2(-delta_, dist_);
    theta_b_ = std::isinf(tmax) ? 0.5f * Pi : std::atan2(tmax - delta_, dist_);
    valid_ = theta_b_ > theta_a_;
}

float EquiangularSampler::sample(float u) const {
    const float theta = (1.f - u) * theta_a_ + u * theta_b_;
    float t = delta_ + dist_ * std::tan(theta);
    // Round-off may leave the interval by an ulp.
    return std::clamp(t, 0.f, tmax_);
}

float EquiangularSampler::pdf(float t) const {
    if (!valid_ || !(t >= 0.f) || !(t <= tmax_)) return 0.f;
    const float x = t - delta_;
    return dist_ / ((theta_b_ - theta_a_) * (dist_ * dist_ + x * x));
}

}  // namespace volguide
