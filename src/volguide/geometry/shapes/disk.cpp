// Mitsuba 3's analytic disk: the unit disk in the z=0 plane mapped by to_world, normal +z
// (inverse-transpose transformed), uv = (r, phi / 2pi).
#include <fmt/format.h>

#include <cmath>

#include "volguide/core/transform.h"
#include "volguide/core/warp.h"
#include "volguide/geometry/shape.h"
#include "volguide/geometry/shapes/shape_plugins.h"
#include "volguide/geometry/surface_frame.h"

namespace volguide {

namespace {

class Disk final : public Shape {
  public:
    explicit Disk(const Properties& props) {
        to_world_ = props.get_transform("to_world");
        flip_normals_ = props.get_bool("flip_normals", false);
        Vec3f ex = to_world_.apply_vector({1, 0, 0}), ey = to_world_.apply_vector({0, 1, 0});
        // Area of the image of the unit disk under an affine map (an ellipse, even with shear).
        area_ = Pi * norm(cross(ex, ey));
        normal_ = to_world_.apply_normal({0, 0, 1});
        float len = norm(normal_);
        if (!(area_ > 0.f) || !std::isfinite(area_) || !(len > 0.f))
            props.fail_at("to_world", "disk: degenerate 'to_world' transform");
        normal_ = normal_ / len;
        if (flip_normals_) normal_ = -normal_;
        to_object_ = to_world_.inverse();
        for (float x : {-1.f, 1.f})
            for (float y : {-1.f, 1.f}) bbox_.expand(to_world_.apply_point({x, y, 0.f}));
        init_common(props);
    }

    BBox3f bbox() const override { return bbox_; }
    float surface_area() const override { return area_; }

    bool intersect(const Ray& ray, float& t_out, Vec2f& prim_uv) const override {
        Point3f o = to_object_.apply_point(ray.o);
        Vec3f d = to_object_.apply_vector(ray.d);  // not normalized: t stays the world distance
        if (d.z == 0.f) return false;
        float t = -o.z / d.z;
        if (!(t > 0.f && t < ray.tmax)) return false;
        float x = o.x + d.x * t, y = o.y + d.y * t;
        if (x * x + y * y > 1.f) return false;
        t_out = t;
        prim_uv = {x, y};
        return true;
    }

    SurfaceInteraction compute_surface_interaction(const Ray& ray, float t, uint32_t prim_index,
                                                   Vec2f) const override {
        Point3f o = to_object_.apply_point(ray.o);
        Vec3f d = to_object_.apply_vector(ray.d);
        float x = o.x + d.x * t, y = o.y + d.y * t;
        SurfaceInteraction si;
        si.t = t;
        si.p = to_world_.apply_point({x, y, 0.f});
        float r = std::sqrt(x * x + y * y);
        float cos_phi = r > 0.f ? x / r : 1.f, sin_phi = r > 0.f ? y / r : 0.f;
        si.uv = uv_of(x, y);
        si.dp_du = to_world_.apply_vector({cos_phi, sin_phi, 0.f});
        si.dp_dv = to_world_.apply_vector({-sin_phi, cos_phi, 0.f}) * (2.f * Pi);
        si.n = normal_;
        si.sh_frame.n = normal_;
        si.shape = this;
        si.prim_index = prim_index;
        finalize_shading_frame(si, ray);
        return si;
    }

    PositionSample sample_position(Point2f u) const override {
        Point2f q = warp::square_to_uniform_disk_concentric(u);
        PositionSample ps;
        ps.p = to_world_.apply_point({q.x, q.y, 0.f});
        ps.n = normal_;
        ps.uv = uv_of(q.x, q.y);
        ps.pdf = 1.f / area_;
        return ps;
    }

    std::string to_string() const override {
        Point3f c = to_world_.apply_point(Point3f(0.f));
        return fmt::format("Disk[center={}, {}, {}, normal={}, {}, {}, area={}]", c.x, c.y, c.z, normal_.x,
                           normal_.y, normal_.z, area_);
    }

  private:
    static Vec2f uv_of(float x, float y) {
        float v = std::atan2(y, x) * InvTwoPi;
        if (v < 0.f) v += 1.f;
        return {std::sqrt(x * x + y * y), v};
    }

    Transform to_world_, to_object_;
    Normal3f normal_;
    BBox3f bbox_;
    float area_ = 0.f;
    bool flip_normals_ = false;
};

}  // namespace

ObjectPtr create_disk_shape(const Properties& props) {
    return std::make_shared<Disk>(props);
}

}  // namespace volguide
