// `spot`: point light at the origin of `to_world` shining along its +z axis with Mitsuba's
// linear-in-angle falloff between beam_width and cutoff_angle, optionally times a projection
// `texture` looked up, as Mitsuba 3, at uv = 0.5 + 0.5 (x, y) / (z tan(cutoff)) of the local
// emission direction (the cutoff cone's tangent square maps to the unit uv square).
#include <cmath>
#include <memory>

#include "volguide/core/transform.h"
#include "volguide/core/warp.h"
#include "volguide/render/emitter.h"
#include "volguide/render/emitters/emitter_common.h"
#include "volguide/render/emitters/emitter_plugins.h"
#include "volguide/render/emitters/spot_falloff.h"
#include "volguide/render/texture.h"

namespace volguide {
namespace {

class SpotEmitter final : public Emitter {
  public:
    explicit SpotEmitter(const Properties& props) {
        intensity_ = nonnegative_color(props, "intensity", Color3(1.f));
        if (props.has("texture")) {
            texture_ = texture_param(props, "texture");
            if (texture_->is_constant())
                props.fail_at("texture", "emitter 'spot': 'texture' must be spatially varying (e.g. a bitmap), as in Mitsuba 3");
        }
        const float cutoff = props.get_float("cutoff_angle", 20.f);
        if (!(cutoff > 0.f && cutoff <= 180.f))
            props.fail_at("cutoff_angle", "emitter 'spot': 'cutoff_angle' must be in (0, 180] degrees");
        const float beam = props.get_float("beam_width", cutoff * 3.f / 4.f);
        if (!(beam > 0.f && beam <= cutoff))
            props.fail_at("beam_width", "emitter 'spot': 'beam_width' must be in (0, cutoff_angle]");
        falloff_ = SpotFalloff(cutoff, beam);
        uv_factor_ = std::tan(deg_to_rad(cutoff));
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
        const Vec3f local = to_local_.apply_vector(-ds.d);
        const float falloff = falloff_(local);
        if (!(falloff > 0.f)) return {ds, Color3(0.f)};
        return {ds, intensity_ * projected(local) * (falloff * inv_dist_sqr)};
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
        const float falloff = falloff_(local);
        if (!(falloff > 0.f)) return rs;
        rs.weight = intensity_ * projected(local) * (falloff * (2.f * Pi * (1.f - cos_cutoff)));
        return rs;
    }

    // Intensity times the falloff integrated over the cone; with a texture, the integral of falloff
    // times texture by a midpoint rule over the cone's uniform parametrisation (an approximation: it
    // only shapes the choice among emitters, never a weight).
    Color3 power() const override {
        if (!texture_) return intensity_ * float(falloff_.solid_angle_integral());
        constexpr int n = 128;
        const float cos_cutoff = falloff_.cos_cutoff();
        Color3 sum(0.f);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                const Vec3f local = warp::square_to_uniform_cone(Point2f((i + 0.5f) / n, (j + 0.5f) / n), cos_cutoff);
                sum += projected(local) * falloff_(local);
            }
        return intensity_ * sum * (2.f * Pi * (1.f - cos_cutoff) / float(n * n));
    }

    std::string to_string() const override { return "SpotEmitter"; }

  private:
    // The projection texture's value for a local emission direction inside the cone (1 without one).
    Color3 projected(const Vec3f& local) const {
        if (!texture_) return Color3(1.f);
        SurfaceInteraction si;
        si.p = position_;
        si.uv = Vec2f(0.5f + 0.5f * local.x / (local.z * uv_factor_), 0.5f + 0.5f * local.y / (local.z * uv_factor_));
        return texture_->eval(si);
    }

    Point3f position_;
    Transform to_world_, to_local_;
    Color3 intensity_;
    SpotFalloff falloff_;
    std::shared_ptr<Texture> texture_;
    float uv_factor_ = 1.f;
};

}  // namespace

ObjectPtr make_spot_emitter(const Properties& props) {
    return std::make_shared<SpotEmitter>(props);
}

}  // namespace volguide
