// `area`: one-sided emitter attached to a shape (Shape::init_common calls set_shape). Emits
// `radiance` on the side the shading normal points to; directions are sampled by the shape's
// solid-angle sampling.
#include <memory>
#include <mutex>

#include "volguide/core/warp.h"
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

    RaySample sample_ray(Point2f u_pos, Point2f u_dir) const override {
        RaySample rs;
        if (!shape_) return rs;
        const PositionSample ps = shape_->sample_position(u_pos);  // uniform by area
        if (!(ps.pdf > 0.f)) return rs;
        // eval() emits on the side of the (shading) normal, which sample_position returns with
        // flip_normals applied: cosine-weighted hemisphere about it, pdf_dir = cos / pi.
        const Vec3f local = warp::square_to_cosine_hemisphere(u_dir);
        const SurfaceInteraction si = emitter_point(ps.p, ps.n, ps.uv, local);
        // Offset like any surface ray: from the exact point, the light hits itself at t ~ 0.
        rs.ray = si.spawn_ray(si.to_world(local));
        rs.n = ps.n;
        // L cos / (pdf_pos cos / pi) = pi L / pdf_pos; eval() gives 0 for a grazing sample.
        rs.weight = eval(si) * (Pi / ps.pdf);
        return rs;
    }

    // Constant radiance: pi L A (Lambertian, one-sided). Textured: the expectation pi L / pdf_pos
    // by a deterministic stratified estimate (computed once).
    Color3 power() const override {
        if (!shape_) return Color3(0.f);
        if (radiance_->is_constant()) return radiance_->mean() * (Pi * shape_->surface_area());
        std::call_once(power_once_, [this] {
            constexpr int n = 256;
            Color3 sum(0.f);
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const PositionSample ps = shape_->sample_position({(i + 0.5f) / n, (j + 0.5f) / n});
                    if (!(ps.pdf > 0.f)) continue;
                    const SurfaceInteraction si = emitter_point(ps.p, ps.n, ps.uv, Vec3f(0.f, 0.f, 1.f));
                    sum += radiance_->eval(si) / ps.pdf;
                }
            power_ = sum * (Pi / float(n * n));
        });
        return power_;
    }

    std::string to_string() const override { return "AreaEmitter"; }

  private:
    SurfaceInteraction emitter_point(const DirectionSample& ds) const {
        SurfaceInteraction si = emitter_point(ds.p, ds.n, ds.uv, Vec3f(0.f));
        si.wi = si.to_local(-ds.d);
        return si;
    }
    // The emitter's surface record at p, seen from the local direction wi.
    SurfaceInteraction emitter_point(const Point3f& p, const Normal3f& n, const Vec2f& uv,
                                     const Vec3f& wi) const {
        SurfaceInteraction si;
        si.p = p;
        si.n = n;
        si.t = 0.f;
        si.uv = uv;
        si.sh_frame = Frame(n);
        si.wi = wi;
        si.shape = shape_;
        return si;
    }

    mutable std::once_flag power_once_;
    mutable Color3 power_{0.f};

    std::shared_ptr<Texture> radiance_;
};

}  // namespace

ObjectPtr make_area_emitter(const Properties& props) {
    return std::make_shared<AreaEmitter>(props);
}

}  // namespace volguide
