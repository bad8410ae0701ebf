// `point`: isotropic point light of radiant `intensity` (W/sr), at `position` or the origin of
// `to_world`.
#include <memory>

#include "volguide/core/warp.h"
#include "volguide/render/emitter.h"
#include "volguide/render/emitters/emitter_common.h"
#include "volguide/render/emitters/emitter_plugins.h"

namespace volguide {
namespace {

class PointEmitter final : public Emitter {
  public:
    explicit PointEmitter(const Properties& props) {
        if (props.has("position")) {
            if (props.has("to_world"))
                props.fail_at("position", "emitter 'point': give either 'position' or 'to_world', not both");
            position_ = props.get_vec3("position");
        } else {
            position_ = props.get_transform("to_world").apply_point(Point3f(0.f));
        }
        if (!all_finite(position_)) props.fail_here("emitter 'point': the position is not finite");
        intensity_ = nonnegative_color(props, "intensity", Color3(1.f));
        flags_ = emitter_flags::DeltaPosition;
        medium_ = emitter_medium(props);
    }

    Color3 eval(const SurfaceInteraction&) const override { return Color3(0.f); }

    std::pair<DirectionSample, Color3> sample_direction(const Interaction& ref, Point2f) const override {
        float inv_dist_sqr;
        DirectionSample ds = delta_point_sample(ref, position_, Vec2f(0.5f, 0.5f), this, inv_dist_sqr);
        return {ds, intensity_ * inv_dist_sqr};
    }

    // Delta emitters are never hit, so any given direction has density zero (as Mitsuba).
    float pdf_direction(const Interaction&, const DirectionSample&) const override { return 0.f; }

    // Uniform direction (pdf 1 / 4 pi): weight = I / pdf = 4 pi I, for every sample.
    RaySample sample_ray(Point2f, Point2f u_dir) const override {
        RaySample rs;
        rs.ray = Ray(position_, warp::square_to_uniform_sphere(u_dir));
        rs.weight = intensity_ * (4.f * Pi);
        return rs;
    }

    // Isotropic intensity integrated over the sphere.
    Color3 power() const override { return intensity_ * (4.f * Pi); }

    std::string to_string() const override { return "PointEmitter"; }

  private:
    Point3f position_;
    Color3 intensity_;
};

}  // namespace

ObjectPtr make_point_emitter(const Properties& props) {
    return std::make_shared<PointEmitter>(props);
}

}  // namespace volguide
