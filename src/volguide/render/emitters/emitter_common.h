#pragma once
// Helpers shared by the emitter plugins: Mitsuba's scene bounding sphere and parameter checks.
#include <string>

#include "volguide/core/bbox.h"
#include "volguide/core/color.h"
#include "volguide/core/frame.h"
#include "volguide/core/properties.h"
#include "volguide/core/warp.h"
#include "volguide/media/medium.h"
#include "volguide/render/emitter.h"

namespace volguide {

// Mitsuba's math::RayEpsilon<float> (1500 ulp of 1), used to pad the scene's bounding sphere.
inline constexpr float MitsubaRayEpsilon = 1500.f * 0x1p-24f;

// The sphere that emitters at infinity place their sample points on: the scene's bounding
// sphere padded by a relative RayEpsilon, or a tiny sphere at the origin for an empty scene.
struct InfiniteEmitterSphere {
    Point3f center{0.f};
    float radius = 1.f;  // Mitsuba's default until the scene is known

    void set(const BBox3f& bounds) {
        if (bounds.valid()) {
            const BSphere s = bounding_sphere(bounds);
            center = s.center;
            radius = std::max(MitsubaRayEpsilon, s.radius * (1.f + MitsubaRayEpsilon));
        } else {
            center = Point3f(0.f);
            radius = MitsubaRayEpsilon;
        }
    }
    // Distance at which sample points are placed: beyond the scene even when the reference point
    // (e.g. a camera) lies outside the scene's bounds.
    float sample_distance(const Point3f& ref) const { return 2.f * std::max(radius, norm(ref - center)); }
    // Area of the sphere's cross-section: photons from infinity are launched through this disk.
    float disk_area() const { return Pi * radius * radius; }
};

// Photon of an emitter at infinity arriving from `to_light` (a sample_direction's ds.d) with
// weight = radiance / pdf_dir. The origin is uniform on the disk of the bounding sphere perpendicular
// to the travel direction, pushed back by one radius so it starts outside the sphere (Mitsuba's
// directional sample_ray). Flux = L cos / (pdf_pos pdf_dir) with cos = 1 and pdf_pos = 1 / disk area.
inline RaySample infinite_emitter_ray(const InfiniteEmitterSphere& sphere, const Vec3f& to_light,
                                      const Color3& weight, Point2f u_pos) {
    RaySample rs;
    const Frame frame(to_light);
    const Point2f q = warp::square_to_uniform_disk_concentric(u_pos);
    rs.ray = Ray(sphere.center + (frame.s * q.x + frame.t * q.y + to_light) * sphere.radius, -to_light);
    rs.weight = weight * sphere.disk_area();
    return rs;
}

// The optional `medium` reference of a non-area emitter (the medium it sits in; nullptr = vacuum).
inline std::shared_ptr<Medium> emitter_medium(const Properties& props) { return get_object_as<Medium>(props, "medium"); }

// Reads a color parameter that must be finite and non-negative (radiance, intensity, ...).
inline Color3 nonnegative_color(const Properties& props, const std::string& name, const Color3& def) {
    const Color3 c = props.get_color(name, def);
    if (!c.is_finite() || c.has_negative())
        props.fail_at(name, "{} '{}': '{}' must be finite and non-negative", props.category(), props.type(),
                      name);
    return c;
}

// Reads a float parameter that must be finite and non-negative.
inline float nonnegative_float(const Properties& props, const std::string& name, float def) {
    const float v = props.get_float(name, def);
    if (!std::isfinite(v) || v < 0.f)
        props.fail_at(name, "{} '{}': '{}' must be finite and non-negative", props.category(), props.type(),
                      name);
    return v;
}

// Direction record towards a point light at `position` (a delta emitter: pdf 1). Sets
// inv_dist_sqr to 1 / distance^2 for the caller's radiometric weight.
inline DirectionSample delta_point_sample(const Interaction& ref, const Point3f& position, Vec2f uv,
                                          const Emitter* emitter, float& inv_dist_sqr) {
    DirectionSample ds;
    ds.p = position;
    ds.n = Normal3f(0.f);
    ds.uv = uv;
    ds.d = position - ref.p;
    ds.dist = norm(ds.d);
    const float inv_dist = 1.f / ds.dist;
    ds.d *= inv_dist;
    ds.pdf = 1.f;
    ds.delta = true;
    ds.emitter = emitter;
    inv_dist_sqr = inv_dist * inv_dist;
    return ds;
}

}  // namespace volguide
