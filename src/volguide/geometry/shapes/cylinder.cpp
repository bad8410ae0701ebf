// Mitsuba 3's analytic `cylinder`: the open tube (no caps) of `radius` (default 1) around the segment
// from `p0` (default 0, 0, 0) to `p1` (default 0, 0, 1), then to_world. In object space the unit tube
// x² + y² = 1, z ∈ [0, 1], placed by to_world · translate(p0) · frame(p1 − p0) · scale(r, r, |p1 − p0|)
// (frame: Mitsuba's coordinate system around the axis). uv = (φ / 2π, z), normal outward
// (flip_normals turns it inwards), area 2π r length.
#include <fmt/format.h>

#include <cmath>

#include "volguide/core/frame.h"
#include "volguide/core/transform.h"
#include "volguide/geometry/shape.h"
#include "volguide/geometry/shapes/shape_plugins.h"
#include "volguide/geometry/surface_frame.h"

namespace volguide {

namespace {

Transform axis_frame(const Vec3f& d) {
    Frame f(d);
    Matrix4 m = Matrix4::identity();
    const Vec3f cols[3] = {f.s, f.t, f.n};
    for (int c = 0; c < 3; ++c) {
        m.m[0][c] = cols[c].x;
        m.m[1][c] = cols[c].y;
        m.m[2][c] = cols[c].z;
    }
    return Transform(m);
}

class Cylinder final : public Shape {
  public:
    explicit Cylinder(const Properties& props) {
        const float radius = props.get_float("radius", 1.f);
        const Vec3f p0 = props.get_vec3("p0", Vec3f(0.f)), p1 = props.get_vec3("p1", Vec3f(0.f, 0.f, 1.f));
        const float length = norm(p1 - p0);
        if (!(radius > 0.f) || !std::isfinite(radius)) props.fail_at("radius", "cylinder: radius must be > 0");
        if (!(length > 0.f) || !std::isfinite(length)) props.fail_here("cylinder: p0 and p1 must differ");
        to_world_ = props.get_transform("to_world") * Transform::translate(p0) * axis_frame((p1 - p0) / length) *
                    Transform::scale(Vec3f(radius, radius, length));
        check_round(props);
        flip_normals_ = props.get_bool("flip_normals", false);
        to_object_ = to_world_.inverse();
        for (float x : {-1.f, 1.f})
            for (float y : {-1.f, 1.f})
                for (float z : {0.f, 1.f}) bbox_.expand(to_world_.apply_point({x, y, z}));
        init_common(props);
    }

    BBox3f bbox() const override { return bbox_; }
    float surface_area() const override { return area_; }

    bool intersect(const Ray& ray, float& t_out, Vec2f& prim_uv) const override {
        const Point3f o = to_object_.apply_point(ray.o);
        const Vec3f d = to_object_.apply_vector(ray.d);  // not normalized: t stays the world distance
        const double a = double(d.x) * d.x + double(d.y) * d.y;
        if (a == 0.0) return false;
        const double b = 2.0 * (double(o.x) * d.x + double(o.y) * d.y);
        const double c = double(o.x) * o.x + double(o.y) * o.y - 1.0;
        const double disc = b * b - 4.0 * a * c;
        if (disc < 0.0) return false;
        // Numerically stable roots (no cancellation between -b and the root).
        const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
        double t0 = q / a, t1 = q != 0.0 ? c / q : t0;
        if (t0 > t1) std::swap(t0, t1);
        for (double t : {t0, t1}) {
            if (!(t > 0.0 && t < ray.tmax)) continue;
            const double z = o.z + d.z * t;
            if (z < 0.0 || z > 1.0) continue;
            t_out = float(t);
            prim_uv = {0.f, 0.f};
            return true;
        }
        return false;
    }

    SurfaceInteraction compute_surface_interaction(const Ray& ray, float t, uint32_t prim_index,
                                                   Vec2f) const override {
        const Point3f o = to_object_.apply_point(ray.o);
        const Vec3f d = to_object_.apply_vector(ray.d);
        Point3f local = o + d * t;
        const float r = std::sqrt(local.x * local.x + local.y * local.y);
        if (r > 0.f) local.x /= r, local.y /= r;  // back onto the tube
        SurfaceInteraction si;
        si.t = t;
        si.p = to_world_.apply_point(local);
        fill_frame(si, local);
        si.shape = this;
        si.prim_index = prim_index;
        finalize_shading_frame(si, ray);
        return si;
    }

    PositionSample sample_position(Point2f u) const override {
        const float phi = 2.f * Pi * u.y;
        const Point3f local(std::cos(phi), std::sin(phi), u.x);
        SurfaceInteraction si;
        fill_frame(si, local);
        PositionSample ps;
        ps.p = to_world_.apply_point(local);
        ps.n = si.n;
        ps.uv = si.uv;
        ps.pdf = 1.f / area_;
        return ps;
    }

    std::string to_string() const override { return fmt::format("Cylinder[area={}]", area_); }

  private:
    // uv, tangents and the outward normal at object-space point `local` on the tube.
    void fill_frame(SurfaceInteraction& si, const Point3f& local) const {
        float phi = std::atan2(local.y, local.x);
        if (phi < 0.f) phi += 2.f * Pi;
        si.uv = {phi * InvTwoPi, local.z};
        si.dp_du = to_world_.apply_vector({-local.y * 2.f * Pi, local.x * 2.f * Pi, 0.f});
        si.dp_dv = to_world_.apply_vector({0.f, 0.f, 1.f});
        Normal3f n = normalize(cross(si.dp_du, si.dp_dv));
        if (flip_normals_) n = -n;
        si.n = n;
        si.sh_frame.n = n;
    }

    // The sections must stay circles (equal radial scales, perpendicular to the axis): Mitsuba's
    // cylinder keeps one radius and one length.
    void check_round(const Properties& props) {
        const Vec3f ex = to_world_.apply_vector({1, 0, 0}), ey = to_world_.apply_vector({0, 1, 0}),
                    ez = to_world_.apply_vector({0, 0, 1});
        const float rx = norm(ex), ry = norm(ey), len = norm(ez);
        const float tol = 1e-4f * std::max(rx, ry);
        if (!(rx > 0.f && len > 0.f) || std::abs(rx - ry) > tol || std::abs(dot(ex, ey)) > tol * rx ||
            std::abs(dot(ex, ez)) > 1e-4f * rx * len || std::abs(dot(ey, ez)) > 1e-4f * ry * len)
            props.fail_at("to_world", "cylinder: to_world must keep the sections circular (no non-uniform radial "
                                      "scale or shear)");
        area_ = 2.f * Pi * rx * len;
    }

    Transform to_world_, to_object_;
    BBox3f bbox_;
    float area_ = 0.f;
    bool flip_normals_ = false;
};

}  // namespace

ObjectPtr create_cylinder_shape(const Properties& props) {
    return std::make_shared<Cylinder>(props);
}

}  // namespace volguide
