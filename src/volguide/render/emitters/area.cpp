// `area`: one-sided emitter attached to a shape (Shape::init_common calls set_shape). Emits
// `radiance` on the side the shading normal points to; directions are sampled by the shape's
// solid-angle sampling.
#include <memory>

#include "volguide/render/emitter.h"
#include "volguide/render/emitters/emitter_common.h"
#include "volguide/render/emitters/emitter_plugins.h"
#include "volguide/render/texture.h"

namespace volguide {
namespace {

class AreaEmitter final : public Emitter {
  public:
    explicit AreaEmitter(const Properties& props) {
        if (props.has("to_world"))
            props.fail_at("to_world",
                          "emitter 'area': 'to_world' is not allowed, the emitter inherits its shape's");
        radiance_ = texture_param(props, "radiance", Color3(1.f));
        if (radiance_->is_constant()) {
            const Color3 c = radiance_->mean();
            if (!c.is_finite() || c.has_negative())
                props.fail_at("radiance", "emitter 'area': 'radiance' must be finite and non-negative");
        }
        flags_ = emitter_flags::Surface;
    }

    Color3 eval(const SurfaceInteraction& si) const override {
        return Frame::cos_theta(si.wi) > 0.f ? radiance_->eval(si) : Color3(0.f);
    }

    std::pair<DirectionSample, Color3> sample_direction(const Interaction& ref, Point2f u) const override {
        if (!shape_) return {DirectionSample{}, Color3(0.f)};  // not attached to a shape
        DirectionSample ds = shape_->sample_direction(ref, u);
        ds.emitter = this;
        ds.delta = false;
        // One-sided: only the front face (normal facing the reference point) emits.
        if (!(dot(ds.d, ds.n) < 0.f) || !(ds.pdf > 0.f)) return {ds, Color3(0.f)};
        // Spatially varying radiance is looked up at the sampled point (uniform area sampling;
        // Mitsuba importance-samples the texture instead, with the same expectation).
        return {ds, radiance_->eval(emitter_point(ds)) / ds.pdf};
    }

    float pdf_direction(const Interaction& ref, const DirectionSample& ds) const override {
        if (!shape_ || !(dot(ds.d, ds.n) < 0.f)) return 0.f;
        return shape_->pdf_direction(ref, ds);
    }

    std::string to_string() const override { return "AreaEmitter"; }

  private:
    SurfaceInteraction emitter_point(const DirectionSample& ds) const {
        SurfaceInteraction si;
        si.p = ds.p;
        si.n = ds.n;
        si.t = 0.f;
        si.uv = ds.uv;
        si.sh_frame = Frame(ds.n);
        si.wi = si.to_local(-ds.d);
        si.shape = shape_;
        return si;
    }

    std::shared_ptr<Texture> radiance_;
};

}  // namespace

ObjectPtr make_area_emitter(const Properties& props) {
    return std::make_shared<AreaEmitter>(props);
}

}  // namespace volguide
