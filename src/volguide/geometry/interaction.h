#pragma once
// Points where light interacts: the shared record between shapes, BSDFs, emitters and integrators.
#include <cstdint>

#include "volguide/core/frame.h"
#include "volguide/core/math.h"
#include "volguide/core/ray.h"

namespace volguide {

class Shape;

// A point in space with an optional surface normal (zero for points inside media).
struct Interaction {
    Point3f p;
    Normal3f n;  // geometric normal, as the shape defines it (not flipped towards the viewer)
    float t = Infinity;

    bool is_valid() const { return t < Infinity; }
    // Offsets the origin along the geometric normal to the side `d` leaves through.
    Point3f offset_origin(const Vec3f& d) const {
        if (n == Normal3f(0.f)) return p;
        float eps = RayEpsilon * (1.f + max_component(abs(p)));
        return p + n * (dot(n, d) >= 0.f ? eps : -eps);
    }
    Ray spawn_ray(const Vec3f& d) const { return Ray(offset_origin(d), d, Infinity); }
    // Ray towards `target`, stopping just short of it (for shadow rays).
    Ray spawn_ray_to(const Point3f& target) const {
        Point3f o = offset_origin(target - p);
        Vec3f d = target - o;
        float dist = norm(d);
        return Ray(o, d / dist, dist * (1.f - ShadowEpsilon));
    }
};

struct SurfaceInteraction : Interaction {
    Vec2f uv;
    Frame sh_frame;  // shading frame (interpolated normal on meshes with vertex normals)
    Vec3f wi;        // direction towards the previous vertex, in the shading frame (world for misses)
    Vec3f dp_du, dp_dv;
    const Shape* shape = nullptr;
    uint32_t prim_index = 0;

    Vec3f to_local(const Vec3f& v) const { return sh_frame.to_local(v); }
    Vec3f to_world(const Vec3f& v) const { return sh_frame.to_world(v); }
};

}  // namespace volguide
