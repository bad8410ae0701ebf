#pragma once
#include "volguide/core/vec.h"

namespace volguide {

// A ray o + t d, t in (0, tmax]. d is unit length everywhere in volguide.
struct Ray {
    Point3f o;
    Vec3f d;
    float tmax = Infinity;
    Ray() = default;
    Ray(const Point3f& o_, const Vec3f& d_, float tmax_ = Infinity) : o(o_), d(d_), tmax(tmax_) {}
    Point3f operator()(float t) const { return o + d * t; }
};

}  // namespace volguide
