#pragma once
// Equiangular distance sampling (Kulla & Fajardo 2012; docs/theory.md §11.2): along the ray o + t d,
// t in [0, tmax] (tmax may be infinite), the density proportional to 1 / |x_t - c|^2 towards a
// point c on a light,
//   t = Δ + D tan((1 - ξ) θa + ξ θb),  p(t) = D / ((θb - θa) (D^2 + (t - Δ)^2)),
// with Δ = (c - o)·d, D the distance from c to the ray's line, θa = atan(-Δ / D), θb = atan((tmax - Δ) / D).
// When c lies (numerically) on the line the strategy is unavailable: valid() is false and pdf() 0,
// so MIS gives the other strategies the full weight consistently.
#include "volguide/core/vec.h"

namespace volguide {

class EquiangularSampler {
public:
    EquiangularSampler(const Point3f& o, const Vec3f& d, float tmax, const Point3f& c);
    bool valid() const { return valid_; }
    // Distance for a uniform sample u in [0, 1).
    float sample(float u) const;
    // Density of sample() at t (0 outside [0, tmax] or when invalid).
    float pdf(float t) const;

private:
    float delta_ = 0.f, dist_ = 0.f, theta_a_ = 0.f, theta_b_ = 0.f, tmax_ = 0.f;
    bool valid_ = false;
};

}  // namespace volguide
