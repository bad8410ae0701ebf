#include "volguide/integrators/guided/walk/guided_surface_sampler.h"

#include <algorithm>
#include <cmath>

namespace volguide {

GuidedSurfaceSampler::GuidedSurfaceSampler(const BSDF& bsdf, const SurfaceInteraction& si, const Vmm* guide,
                                           float bsdf_prob)
    : bsdf_(&bsdf), si_(&si) {
    const float alpha = std::isnan(bsdf_prob) ? 1.f : std::clamp(bsdf_prob, 0.f, 1.f);
    // Only diffuse reflectors: the guide stands for f cos of a Lambertian lobe on the facing side.
    if (!guide || guide->count == 0 || alpha >= 1.f || bsdf.flags() != bsdf_flags::DiffuseReflection) return;
    guide_ = guide;
    alpha_ = alpha;
}

float GuidedSurfaceSampler::pdf(const BSDFContext& ctx, const Vec3f& wo_local) const {
    const float p_bsdf = bsdf_->pdf(ctx, *si_, wo_local);
    if (!guide_) return p_bsdf;
    return alpha_ * p_bsdf + (1.f - alpha_) * guide_->pdf(si_->to_world(wo_local));
}

GuidedSurfaceSampler::Sample GuidedSurfaceSampler::sample(const BSDFContext& ctx, float u_strategy, float u1,
                                                          Point2f u2) const {
    Sample s;
    if (!guide_) {
        auto [bs, weight] = bsdf_->sample(ctx, *si_, u1, u2);
        s.bs = bs;
        s.weight = weight;
        return s;
    }
    Vec3f wo;
    if (u_strategy < alpha_) {
        const BSDFSample bs = bsdf_->sample(ctx, *si_, u1, u2).first;
        if (!(bs.pdf > 0.f)) return s;  // the BSDF failed (e.g. seen from behind): no direction
        wo = bs.wo;
    } else {
        wo = si_->to_local(guide_->sample(u2));
        s.guided = true;
    }
    s.bs.wo = wo;
    s.bs.pdf = pdf(ctx, wo);
    s.bs.eta = 1.f;
    // Only diffuse reflectors are guided (see the constructor), so the lobe is known.
    s.bs.sampled_flags = bsdf_flags::DiffuseReflection;
    if (!(s.bs.pdf > 0.f)) {
        s.bs.pdf = 0.f;
        return s;
    }
    s.weight = bsdf_->eval(ctx, *si_, wo) * (1.f / s.bs.pdf);
    return s;
}

}  // namespace volguide
