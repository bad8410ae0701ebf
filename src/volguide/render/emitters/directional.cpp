// `directional`: distant light delivering `irradiance` (W/m^2 perpendicular to the beam) along
// `direction`, or along the +z axis of `to_world`.
#include <memory>

#include "volguide/render/emitter.h"
#include "volguide/render/emitters/emitter_common.h"
#include "volguide/render/emitters/emitter_plugins.h"

namespace volguide {
namespace {

class DirectionalEmitter final : public Emitter {
  public:
    explicit DirectionalEmitter(const Properties& props) {
        Vec3f d;
        if (props.has("direction")) {
            if (props.has("to_world"))
                props.fail_at("direction",
                              "emitter 'directional': give either 'direction' or 'to_world', not both");
            d = props.get_vec3("direction");
        } else {
            d = props.get_transform("to_world").apply_vector(Vec3f(0.f, 0.f, 1.f));
        }
        if (!all_finite(d) || !(squared_norm(d) > 0.f))
            props.fail_here("emitter 'directional': the direction must be a finite non-zero vector");
        direction_ = normalize(d);
        irradiance_ = nonnegative_color(props, "irradiance", Color3(1.f));
        flags_ = emitter_flags::Infinite | emitter_flags::DeltaDirection;
        medium_ = emitter_medium(props);
    }

    void set_scene_bounds(const BBox3f& bounds) override { sphere_.set(bounds); }

    Color3 eval(const SurfaceInteraction&) const override { return Color3(0.f); }

    std::pair<DirectionSample, Color3> sample_direction(const Interaction& ref, Point2f) const override {
        DirectionSample ds;
        ds.p = ref.p - direction_ * sphere_.sample_distance(ref.p);
        ds.n = direction_;
        ds.uv = Vec2f(0.f, 0.f);
        ds.d = -direction_;
        ds.dist = Infinity;
        ds.pdf = 1.f;
        ds.delta = true;
        ds.emitter = this;
        return {ds, irradiance_};
    }

    float pdf_direction(const Interaction&, const DirectionSample&) const override { return 0.f; }

    // Every photon travels along direction_; origins cover the bounding sphere's disk uniformly,
    // so weight = irradiance x disk area (pdf_pos = 1 / disk area, delta direction).
    RaySample sample_ray(Point2f u_pos, Point2f) const override {
        return infinite_emitter_ray(sphere_, -direction_, irradiance_, u_pos);
    }

    // Flux through the bounding sphere's cross-section: E pi R^2.
    Color3 power() const override { return irradiance_ * sphere_.disk_area(); }

    std::string to_string() const override { return "DirectionalEmitter"; }

  private:
    Vec3f direction_;  // direction of propagation
    Color3 irradiance_;
    InfiniteEmitterSphere sphere_;
};

}  // namespace

ObjectPtr make_directional_emitter(const Properties& props) {
    return std::make_shared<DirectionalEmitter>(props);
}

}  // namespace volguide
