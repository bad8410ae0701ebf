// `constant`: uniform environment of `radiance`, sampled uniformly over the sphere of directions.
#include <memory>

#include "volguide/core/warp.h"
#include "volguide/render/emitter.h"
#include "volguide/render/emitters/emitter_common.h"
#include "volguide/render/emitters/emitter_plugins.h"

namespace volguide {
namespace {

class ConstantEmitter final : public Emitter {
  public:
    explicit ConstantEmitter(const Properties& props) {
        radiance_ = nonnegative_color(props, "radiance", Color3(1.f));
        flags_ = emitter_flags::Infinite;
        medium_ = emitter_medium(props);
    }

    void set_scene_bounds(const BBox3f& bounds) override { sphere_.set(bounds); }

    Color3 eval(const SurfaceInteraction&) const override { return radiance_; }

    std::pair<DirectionSample, Color3> sample_direction(const Interaction& ref, Point2f u) const override {
        DirectionSample ds;
        ds.d = warp::square_to_uniform_sphere(u);
        ds.p = ref.p + ds.d * sphere_.sample_distance(ref.p);
        ds.n = -ds.d;
        ds.uv = Vec2f(0.f, 0.f);
        ds.dist = Infinity;
        ds.pdf = warp::square_to_uniform_sphere_pdf();
        ds.delta = false;
        ds.emitter = this;
        return {ds, radiance_ / ds.pdf};
    }

    float pdf_direction(const Interaction&, const DirectionSample&) const override {
        return warp::square_to_uniform_sphere_pdf();
    }

    // Direction by the emitter's own (uniform) sampling, origin on the bounding sphere's disk.
    RaySample sample_ray(Point2f u_pos, Point2f u_dir) const override {
        Interaction ref;
        ref.p = sphere_.center;
        auto [ds, weight] = sample_direction(ref, u_dir);
        return infinite_emitter_ray(sphere_, ds.d, weight, u_pos);
    }

    // E[weight] = disk area x integral of L over the sphere of directions = pi R^2 x 4 pi L.
    Color3 power() const override { return radiance_ * (4.f * Pi * sphere_.disk_area()); }

    std::string to_string() const override { return "ConstantEmitter"; }

  private:
    Color3 radiance_;
    InfiniteEmitterSphere sphere_;
};

}  // namespace

ObjectPtr make_constant_emitter(const Properties& props) {
    return std::make_shared<ConstantEmitter>(props);
}

}  // namespace volguide
