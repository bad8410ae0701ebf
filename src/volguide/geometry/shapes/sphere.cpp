// Mitsuba 3's analytic sphere: center/radius folded into to_world, exact ray intersection in
// double precision, uv = (phi / 2pi, theta / pi) in object space, and visible-cone sampling from
// reference points outside the sphere (Akalin's "sampling the visible sphere").
#include <fmt/format.h>

#include <cmath>
#include <cstdio>

#include "volguide/core/transform.h"
#include "volguide/core/warp.h"
#include "volguide/geometry/shape.h"
#include "volguide/geometry/shapes/shape_plugins.h"
#include "volguide/geometry/surface_frame.h"

namespace volguide {

namespace {

double linear_determinant(const Matrix4& m) {
    const auto& a = m.m;
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

class Sphere final : public Shape {
  public:
    explicit Sphere(const Properties& props) {
        flip_normals_ = props.get_bool("flip_normals", false);
        Vec3f center = props.get_vec3("center", Vec3f(0.f));
        float radius = props.get_float("radius", 1.f);
        if (!all_finite(center)) props.fail_at("center", "sphere: 'center' must be finite");
        if (!(radius > 0.f) || !std::isfinite(radius))
            props.fail_at("radius", "sphere: 'radius' must be positive and finite (got {})", radius);
        to_world_ =
            props.get_transform("to_world") * Transform::translate(center) * Transform::scale(Vec3f(radius));

        Vec3f ex = to_world_.apply_vector({1, 0, 0}), ey = to_world_.apply_vector({0, 1, 0}),
              ez = to_world_.apply_vector({0, 0, 1});
        float lx = norm(ex), ly = norm(ey), lz = norm(ez);
        if (std::abs(lx - ly) > 1e-5f * lx || std::abs(lx - lz) > 1e-5f * lx ||
            std::abs(dot(ex, ey)) > 1e-5f * lx * ly || std::abs(dot(ex, ez)) > 1e-5f * lx * lz ||
            std::abs(dot(ey, ez)) > 1e-5f * ly * lz)
            fmt::print(stderr,
                       "volguide: warning: {}: sphere 'to_world' should not contain shear or "
                       "non-uniform scaling\n",
                       props.location().str());
        radius_ = lx;
        center_ = to_world_.apply_point(Point3f(0.f));
        if (!(radius_ > 0.f) || !std::isfinite(radius_) || !all_finite(center_))
            props.fail_at("to_world", "sphere: degenerate 'to_world' transform");
        // A mirroring transform turns the sphere inside out (as Mitsuba, which flips the normals).
        if (linear_determinant(to_world_.matrix()) < 0.0) flip_normals_ = !flip_normals_;
        to_object_ = to_world_.inverse();
        inv_area_ = 1.f / surface_area();
        init_common(props);
    }

    BBox3f bbox() const override { return {center_ - Vec3f(radius_), center_ + Vec3f(radius_)}; }
    float surface_area() const override { return 4.f * Pi * radius_ * radius_; }

    bool intersect(const Ray& ray, float& t_out, Vec2f& prim_uv) const override {
        // Solve from the point of the ray closest to the center: avoids the cancellation of the
        // textbook quadratic when the origin is far away.
        Vec3d c(center_), d(ray.d);
        Vec3d o = Vec3d(ray.o) - c;
        double dd = dot(d, d);
        double plane_t = -dot(o, d) / dd;
        Vec3d op = o + d * plane_t;
        double r = radius_;
        double b = 2.0 * dot(op, d), cc = dot(op, op) - r * r;
        double disc = b * b - 4.0 * dd * cc;
        if (!(disc >= 0.0)) return false;
        double root = std::sqrt(disc);
        double q = -0.5 * (b + std::copysign(root, b));
        double x0, x1;
        if (q == 0.0) {
            x0 = x1 = -0.5 * b / dd;
        } else {
            x0 = q / dd;
            x1 = cc / q;
            if (x0 > x1) std::swap(x0, x1);
        }
        double near_t = plane_t + x0, far_t = plane_t + x1, tmax = ray.tmax;
        double t;
        if (near_t > 0.0 && near_t < tmax)
            t = near_t;
        else if (far_t > 0.0 && far_t < tmax)
            t = far_t;
        else
            return false;
        if (!(float(t) > 0.f)) return false;
        t_out = float(t);
        prim_uv = {0.f, 0.f};
        return true;
    }

    SurfaceInteraction compute_surface_interaction(const Ray& ray, float t, uint32_t prim_index,
                                                   Vec2f) const override {
        SurfaceInteraction si;
        si.t = t;
        Vec3d c(center_);
        Vec3d n = normalize(Vec3d(ray.o) + Vec3d(ray.d) * double(t) - c);
        // Re-project onto the sphere for accuracy.
        si.p = Point3f(c + n * double(radius_));
        Normal3f nf(n);
        Point3f local = to_object_.apply_point(si.p);
        fill_parameterization(local, si.uv, si.dp_du, si.dp_dv);
        if (flip_normals_) nf = -nf;
        si.n = nf;
        si.sh_frame.n = nf;
        si.shape = this;
        si.prim_index = prim_index;
        finalize_shading_frame(si, ray);
        return si;
    }

    PositionSample sample_position(Point2f u) const override {
        Vec3f local = warp::square_to_uniform_sphere(u);
        PositionSample ps;
        ps.p = to_world_.apply_point(local);
        ps.n = normalize(ps.p - center_);
        if (flip_normals_) ps.n = -ps.n;
        ps.pdf = inv_area_;
        ps.uv = uv_of(local);
        return ps;
    }
    float pdf_position(const PositionSample&) const override { return inv_area_; }

    DirectionSample sample_direction(const Interaction& ref, Point2f u) const override {
        DirectionSample ds;
        ds.emitter = emitter();
        Vec3f dc_v = center_ - ref.p;
        float dc_2 = squared_norm(dc_v);
        Vec3f n;
        if (sees_from_outside(dc_2)) {
            float inv_dc = 1.f / std::sqrt(dc_2);
            float sin_theta_max = radius_ * inv_dc, sin_theta_max_2 = sin_theta_max * sin_theta_max;
            float inv_sin_theta_max = 1.f / sin_theta_max;
            float cos_theta_max = safe_sqrt(1.f - sin_theta_max_2);
            // Small cones: Taylor expansion avoids the cancellation in 1 - cos^2.
            float sin_theta_2 = sin_theta_max_2 > 0.00068523f  // sin^2(1.5 deg)
                                    ? 1.f - sqr(std::fma(cos_theta_max - 1.f, u.x, 1.f))
                                    : sin_theta_max_2 * u.x;
            float cos_theta = safe_sqrt(1.f - sin_theta_2);
            // Angle at the center between the axis towards ref and the sampled surface point.
            float cos_alpha = sin_theta_2 * inv_sin_theta_max +
                              cos_theta * safe_sqrt(1.f - sin_theta_2 * sqr(inv_sin_theta_max));
            float sin_alpha = safe_sqrt(1.f - cos_alpha * cos_alpha);
            float phi = 2.f * Pi * u.y;
            n = Frame(dc_v * -inv_dc)
                    .to_world({std::cos(phi) * sin_alpha, std::sin(phi) * sin_alpha, cos_alpha});
            ds.p = center_ + n * radius_;
            fill_distance(ref, ds);
            ds.pdf = ds.dist > 0.f ? cone_pdf(sin_theta_max_2, cos_theta_max) : 0.f;
        } else {
            n = warp::square_to_uniform_sphere(u);
            ds.p = center_ + n * radius_;
            fill_distance(ref, ds);
            float cos_light = absdot(ds.d, n);
            ds.pdf = cos_light > 0.f ? inv_area_ * ds.dist * ds.dist / cos_light : 0.f;
        }
        ds.n = flip_normals_ ? -n : n;
        ds.uv = uv_of(to_object_.apply_point(ds.p));
        return ds;
    }

    float pdf_direction(const Interaction& ref, const DirectionSample& ds) const override {
        float dc_2 = squared_norm(center_ - ref.p);
        if (sees_from_outside(dc_2)) {
            float sin_theta_max_2 = radius_ * radius_ / dc_2;
            return cone_pdf(sin_theta_max_2, safe_sqrt(1.f - sin_theta_max_2));
        }
        float cos_light = absdot(ds.d, ds.n);
        return cos_light > 0.f ? inv_area_ * ds.dist * ds.dist / cos_light : 0.f;
    }

    std::string to_string() const override {
        return fmt::format("Sphere[center={}, {}, {}, radius={}, flip_normals={}]", center_.x, center_.y,
                           center_.z, radius_, flip_normals_);
    }

  private:
    // Cone sampling applies when the reference point is outside the sphere (with Mitsuba's
    // margin, so that points on the surface use it too, and points on an inward-facing sphere
    // do not). Shared by sample_direction and pdf_direction so that they always agree.
    bool sees_from_outside(float dc_2) const {
        float radius_adj = radius_ * (flip_normals_ ? 1.f + RayEpsilon : 1.f - RayEpsilon);
        return dc_2 > radius_adj * radius_adj;
    }
    // 1 / (2 pi (1 - cos_theta_max)), with 1 - cos computed without cancellation.
    static float cone_pdf(float sin_theta_max_2, float cos_theta_max) {
        float one_minus_cos = sin_theta_max_2 < 1.f ? sin_theta_max_2 / (1.f + cos_theta_max) : 1.f;
        return InvTwoPi / one_minus_cos;
    }
    static void fill_distance(const Interaction& ref, DirectionSample& ds) {
        Vec3f d = ds.p - ref.p;
        ds.dist = norm(d);
        ds.d = ds.dist > 0.f ? d / ds.dist : Vec3f(0.f);
    }
    static Vec2f uv_of(const Point3f& local) {
        float theta = safe_acos(local.z / std::max(norm(local), 1e-30f));
        float phi = std::atan2(local.y, local.x);
        if (phi < 0.f) phi += 2.f * Pi;
        return {phi * InvTwoPi, theta * InvPi};
    }
    void fill_parameterization(const Point3f& local, Vec2f& uv, Vec3f& dp_du, Vec3f& dp_dv) const {
        uv = uv_of(local);
        dp_du = to_world_.apply_vector({-local.y, local.x, 0.f}) * (2.f * Pi);
        float rd = std::sqrt(local.x * local.x + local.y * local.y);
        Vec3f dv_local =
            rd > 0.f ? Vec3f(local.z * local.x / rd, local.z * local.y / rd, -rd) : Vec3f(1.f, 0.f, 0.f);
        dp_dv = to_world_.apply_vector(dv_local) * Pi;
    }

    Transform to_world_, to_object_;
    Point3f center_;
    float radius_ = 1.f, inv_area_ = 0.f;
    bool flip_normals_ = false;
};

}  // namespace

ObjectPtr create_sphere_shape(const Properties& props) {
    return std::make_shared<Sphere>(props);
}

}  // namespace volguide
