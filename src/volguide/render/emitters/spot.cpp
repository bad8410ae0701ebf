// `spot`: point light at the origin of `to_world` shining along its +z axis with Mitsuba's
// linear-in-angle falloff between beam_width and cutoff_angle.
#include <memory>

#include "volguide/core/transform.h"
#include "volguide/core/warp.h"
#include "volguide/render/emitter.h"
#include "volguide/render/emitters/emitter_common.h"
#include "volguide/render/emitters/emitter_plugins.h"
#include "volguide/render/emitters/spot_falloff.h"

namespace volguide {
namespace {

class SpotEmitter final : public Emitter {
  public:
    explicit SpotEmitter(const Properties& props) {
        if (props.has("texture"))
            props.fail_at("texture", "emitter 'spot': projection textures ('texture') are not supported");
        intensity_ = nonnegative_color(props, "intensity", Color3(1.f));
        const float cutoff = props.get_float("cutoff_angle", 20.f);
        if (!(cutoff > 0.f && cutoff <= 180.f))
            props.fail_at("cutoff_angle", "emitter 'spot': 'cutoff_angle' must be in (0, 180] degrees");
        const float beam = props.get_float("beam_width", cutoff * 3.f / 4.f);
        if (!(beam > 0.f && beam <= cutoff))
            props.fail_at("beam_width", "emitter 'spot': 'beam_width' must be in (0, cutoff_angle]");
        falloff_ = SpotFalloff(cutoff, beam);
        const Transform to_world = props.get_transform("to_world");
        to_world_ = to_world;
        to_local_ = to_world.inverse();
        position_ = to_world.apply_point(Point3f(0.f));
        flags_ = emitter_flags::DeltaPosition;
        medium_ = emitter_medium(props);
    }

    Color3 eval(const SurfaceInteraction&) const override { return Color3(0.f); }

    std::pair<DirectionSample, Color3> sample_direction(const Interaction& ref, Point2f) const override {
        float inv_dist_sqr;
        DirectionSample ds = delta_point_sample(ref, position_, Vec2f(0.f, 0.f), this, inv_dist_sqr);
        const float falloff = falloff_(to_local_.apply_vector(-ds.d));
        return {ds, intensity_ * (falloff * inv_dist_sqr)};
    }

    float pdf_direction(const Interaction&, const DirectionSample&) const override { return 0.f; }

    // Uniform direction in the cutoff cone (pdf 1 / (2 pi (1 - cos cutoff))), weighted by the same
    // falloff sample_direction applies: weight = I falloff / pdf. The cone is mapped by to_world,
    // assumed rigid (up to uniform scale) as in Mitsuba.
    RaySample sample_ray(Point2f, Point2f u_dir) const override {
        const float cos_cutoff = falloff_.cos_cutoff();
        const Vec3f local = warp::square_to_uniform_cone(u_dir, cos_cutoff);
        RaySample rs;
        rs.ray = Ray(position_, normalize(to_world_.apply_vector(local)));
        // 1 / pdf = 2 pi (1 - cos cutoff) (not square_to_uniform_cone_pdf: a rounded sample on the rim
        // would get pdf 0; the falloff is 0 there anyway).
        rs.weight = intensity_ * (falloff_(local) * (2.f * Pi * (1.f - cos_cutoff)));
        return rs;
    }

    // Intensity times the falloff integrated over the cone.
    Color3 power() const override { return intensity_ * float(falloff_.solid_angle_integral()); }

    std::string to_string() const override { return "SpotEmitter"; }

  private:
    Point3f position_;
    Transform to_world_, to_local_;
    Color3 intensity_;
    SpotFalloff falloff_;
};

}  // namespace

ObjectPtr make_spot_emitter(const Properties& props) {
    return std::make_shared<SpotEmitter>(props);
}

}  // namespace volguide
