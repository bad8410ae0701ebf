#pragma once
// A nested BSDF evaluated in a perturbed shading frame (bumpmap, normalmap): the subclass says how the
// frame is perturbed; carrying wi and wo into that frame, and giving zero to a direction on opposite
// sides of the two frames' surfaces (as Mitsuba 3), is done here once.
#include <memory>
#include <utility>

#include "volguide/core/frame.h"
#include "volguide/render/bsdf.h"

namespace volguide {

class ShadingFrameBSDF : public BSDF {
  public:
    std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si, float sample1,
                                         Point2f sample2) const final {
        const SurfaceInteraction p = perturbed(si);
        auto [bs, weight] = nested_->sample(ctx, p, sample1, sample2);
        if (weight.is_black()) return {bs, weight};
        const Vec3f wo = si.to_local(p.to_world(bs.wo));
        if (!(bs.wo.z * wo.z > 0.f)) return {BSDFSample{}, Color3(0.f)};
        bs.wo = wo;
        return {bs, weight};
    }
    Color3 eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const final {
        const SurfaceInteraction p = perturbed(si);
        const Vec3f pwo = p.to_local(si.to_world(wo));
        if (!(wo.z * pwo.z > 0.f)) return Color3(0.f);
        return nested_->eval(ctx, p, pwo);
    }
    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const final {
        const SurfaceInteraction p = perturbed(si);
        const Vec3f pwo = p.to_local(si.to_world(wo));
        if (!(wo.z * pwo.z > 0.f)) return 0.f;
        return nested_->pdf(ctx, p, pwo);
    }

  protected:
    // The interaction with the perturbed shading frame (world space) and wi expressed in it.
    virtual SurfaceInteraction perturbed(const SurfaceInteraction& si) const = 0;
    // si with the shading frame f and wi carried into it.
    static SurfaceInteraction with_frame(const SurfaceInteraction& si, const Frame& f) {
        SurfaceInteraction out(si);
        out.sh_frame = f;
        out.wi = f.to_local(si.to_world(si.wi));
        return out;
    }

    std::shared_ptr<BSDF> nested_;
};

}  // namespace volguide
