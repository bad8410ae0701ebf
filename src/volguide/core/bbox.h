#pragma once
#include "volguide/core/ray.h"

namespace volguide {

struct BBox3f {
    Point3f lo{Infinity, Infinity, Infinity};
    Point3f hi{-Infinity, -Infinity, -Infinity};
    BBox3f() = default;
    BBox3f(const Point3f& a, const Point3f& b) : lo(min(a, b)), hi(max(a, b)) {}
    bool valid() const { return lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z; }
    void expand(const Point3f& p) { lo = min(lo, p); hi = max(hi, p); }
    void expand(const BBox3f& b) { lo = min(lo, b.lo); hi = max(hi, b.hi); }
    Vec3f extents() const { return hi - lo; }
    Point3f center() const { return (lo + hi) * 0.5f; }
    bool contains(const Point3f& p) const {
        return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
    }
    // Slab test; on success [t0, t1] is the overlap of the ray's line with the box.
    bool ray_intersect(const Ray& r, float& t0, float& t1) const {
        t0 = -Infinity;
        t1 = Infinity;
        for (int i = 0; i < 3; ++i) {
            float inv = 1.f / r.d[i];
            float a = (lo[i] - r.o[i]) * inv, b = (hi[i] - r.o[i]) * inv;
            if (a > b) std::swap(a, b);
            t0 = std::max(t0, a);
            t1 = std::min(t1, b);
        }
        return t0 <= t1;
    }
};

struct BSphere {
    Point3f center;
    float radius = 0.f;
};

inline BSphere bounding_sphere(const BBox3f& b) {
    return b.valid() ? BSphere{b.center(), norm(b.hi - b.center())} : BSphere{Point3f(0.f), 0.f};
}

}  // namespace volguide
