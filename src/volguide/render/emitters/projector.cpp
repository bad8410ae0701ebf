// `projector` (Mitsuba 3): a point light at the origin of `to_world` projecting the image
// `irradiance` (a texture, default 1) through a pinhole with horizontal field of view `fov`
// (`fov_axis` / `focal_length` as the perspective camera, on an image of the texture's aspect),
// along +z, times `scale`. A point p (local (x, y, z), z > 0) sees the texel at
//   uv = (1/2 - x / (2 t z), 1/2 - a y / (2 t z)),  t = tan(fov / 2), a = width / height,
// and, as Mitsuba's weight, irradiance(uv) pi scale / (z^2 cos theta) with cos theta the angle
// between the axis and the direction to p (so a surface facing the light at z = 1 receives
// pi irradiance(uv) on the axis); nothing outside the image. Theory: docs/theory.md §19.
#include <cmath>
#include <memory>

#include "volguide/core/transform.h"
#include "volguide/render/emitter.h"
#include "volguide/render/emitters/emitter_common.h"
#include "volguide/render/emitters/emitter_plugins.h"
#include "volguide/render/sensors/perspective.h"
#include "volguide/render/texture.h"

namespace volguide {
namespace {

// The horizontal field of view of Mitsuba's parse_fov on an image of the given aspect.
float projector_x_fov(const Properties& props, double aspect) {
    if (props.has("fov") && props.has("focal_length"))
        props.fail_at("focal_length", "emitter 'projector': give either 'fov' or 'focal_length', not both");
    const bool has_fov = props.has("fov");
    const char* fov_param = has_fov ? "fov" : "focal_length";
    double fov = 0.0;
    std::string axis = "diagonal";
    if (has_fov) {
        fov = props.get_float("fov");
        axis = props.get_string("fov_axis", "x");
    } else {
        const std::string f = props.get_string("focal_length", "50mm");
        fov = focal_length_to_diagonal_fov(f);
        if (fov < 0) props.fail_at("focal_length", "emitter 'projector': could not parse focal_length '{}'", f);
    }
    if (!(fov > 0.0 && fov < 180.0))
        props.fail_at(fov_param, "emitter 'projector': the field of view must be in (0, 180) degrees, got {}", fov);
    double x_fov = 0.0;
    try {
        x_fov = horizontal_fov(fov, axis, aspect);
    } catch (const std::invalid_argument& e) {
        props.fail_at("fov_axis", "emitter 'projector': {}, got '{}'", e.what(), axis);
    }
    if (!(x_fov > 0.0 && x_fov < 180.0))
        props.fail_at(fov_param, "emitter 'projector': the horizontal field of view must be in (0, 180), got {}", x_fov);
    return float(x_fov);
}

class ProjectorEmitter final : public Emitter {
  public:
    explicit ProjectorEmitter(const Properties& props) {
        scale_ = nonnegative_float(props, "scale", 1.f);
        irradiance_ = texture_param(props, "irradiance", Color3(1.f));
        const auto [w, h] = irradiance_->resolution();
        aspect_ = float(w) / float(h);
        tan_half_ = std::tan(0.5f * deg_to_rad(projector_x_fov(props, double(w) / double(h))));
        to_world_ = props.get_transform("to_world");
        to_local_ = to_world_.inverse();
        position_ = to_world_.apply_point(Point3f(0.f));
        axis_ = to_world_.apply_vector(Vec3f(0.f, 0.f, 1.f));
        if (!all_finite(position_) || !(squared_norm(axis_) > 0.f))
            props.fail_at("to_world", "emitter 'projector': 'to_world' must be finite and invertible");
        flags_ = emitter_flags::DeltaPosition;
        medium_ = emitter_medium(props);
        power_ = mean_irradiance() * (Pi * scale_ * image_area());
    }

    Color3 eval(const SurfaceInteraction&) const override { return Color3(0.f); }

    std::pair<DirectionSample, Color3> sample_direction(const Interaction& ref, Point2f) const override {
        float inv_dist_sqr;
        DirectionSample ds = delta_point_sample(ref, position_, Vec2f(0.5f, 0.5f), this, inv_dist_sqr);
        const Vec3f local = to_local_.apply_point(ref.p);
        const float cos_theta = -dot(axis_, ds.d);
        if (!(local.z > 0.f) || !(cos_theta > 0.f)) return {ds, Color3(0.f)};
        const Vec2f uv(0.5f - 0.5f * local.x / (tan_half_ * local.z),
                       0.5f - 0.5f * aspect_ * local.y / (tan_half_ * local.z));
        if (!(uv.x >= 0.f && uv.x <= 1.f && uv.y >= 0.f && uv.y <= 1.f)) return {ds, Color3(0.f)};
        ds.uv = uv;
        return {ds, irradiance_at(uv) * (Pi * scale_ / (local.z * local.z * cos_theta))};
    }

    float pdf_direction(const Interaction&, const DirectionSample&) const override { return 0.f; }

    // A uniform point of the image: direction through it, weight = irradiance pi scale x image area
    // at unit distance (the image's pdf is 1 in uv), whose mean is power().
    RaySample sample_ray(Point2f, Point2f u_dir) const override {
        const Vec2f uv(u_dir.x, u_dir.y);
        const Vec3f local((1.f - 2.f * uv.x) * tan_half_, (1.f - 2.f * uv.y) * tan_half_ / aspect_, 1.f);
        RaySample rs;
        rs.ray = Ray(position_, normalize(to_world_.apply_vector(local)));
        rs.weight = irradiance_at(uv) * (Pi * scale_ * image_area());
        return rs;
    }

    Color3 power() const override { return power_; }

    std::string to_string() const override { return "ProjectorEmitter"; }

  private:
    Color3 irradiance_at(const Vec2f& uv) const {
        SurfaceInteraction si;
        si.p = position_;
        si.uv = uv;
        return irradiance_->eval(si);
    }
    // The image rectangle's area on the plane z = 1 of the local frame.
    float image_area() const { return 4.f * tan_half_ * tan_half_ / aspect_; }
    // The image's mean over uv: exact for a constant, a 256 x 256 midpoint rule otherwise (power()
    // only shapes the choice among emitters, never a weight).
    Color3 mean_irradiance() const {
        if (irradiance_->is_constant()) return irradiance_at(Vec2f(0.5f, 0.5f));
        constexpr int n = 256;
        Color3 sum(0.f);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) sum += irradiance_at(Vec2f((i + 0.5f) / n, (j + 0.5f) / n));
        return sum / float(n * n);
    }

    std::shared_ptr<Texture> irradiance_;
    float scale_ = 1.f, aspect_ = 1.f, tan_half_ = 1.f;
    Transform to_world_, to_local_;
    Point3f position_;
    Vec3f axis_;
    Color3 power_{0.f};
};

}  // namespace

ObjectPtr make_projector_emitter(const Properties& props) {
    return std::make_shared<ProjectorEmitter>(props);
}

}  // namespace volguide
