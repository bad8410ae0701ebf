#pragma once
// Guided directional sampling at a diffuse surface vertex (volguide extension; the surface
// counterpart of guiding/guided_direction.h): a one-sample defensive mixture
//   p(wo) = alpha_b p_bsdf(wo) + (1 - alpha_b) V(wo)
// of the BSDF's own sampling and a guide VMM V in world space (guiding/surface_guide.h: the
// leaf's incident VMM, or its product with the cosine lobe). Weights are f(wi, wo) |cos| / p(wo)
// with the exact BSDF; pdf() is the full mixture, which MIS with NEE must use on both sides.
// Guide directions below the surface are valid samples of the mixture with weight 0.
//
// Only BSDFs with a single diffuse reflection lobe are guided (the guide stands for f cos of a
// Lambertian lobe on the facing side). Without a guide (null), for any other BSDF or with
// alpha_b = 1 the sampler is exactly the BSDF's: sample() then
// calls BSDF::sample with the same random numbers and draws nothing else.
#include "volguide/render/bsdf.h"
#include "volguide/vmm/vmm.h"

namespace volguide {

class GuidedSurfaceSampler {
  public:
    static constexpr float kDefaultBsdfProbability = 0.5f;  // Open PGL's bsdfProbability default

    // `bsdf`, `si` and `guide` (world-space, may be null) must outlive the sampler. bsdf_prob =
    // alpha_b, clamped to [0, 1] (NaN: 1).
    GuidedSurfaceSampler(const BSDF& bsdf, const SurfaceInteraction& si, const Vmm* guide,
                         float bsdf_prob = kDefaultBsdfProbability);

    struct Sample {
        BSDFSample bs;        // local wo, the mixture pdf, the sampled lobe
        Color3 weight{0.f};   // f |cos| / pdf
        bool guided = false;  // drawn from the guide
    };
    // u_strategy < alpha_b: the BSDF (with u1, u2); otherwise the guide (with u2). When guided()
    // is false u_strategy is ignored and the result is BSDF::sample's.
    Sample sample(const BSDFContext& ctx, float u_strategy, float u1, Point2f u2) const;
    // The mixture pdf of a local direction (BSDF::pdf when not guided).
    float pdf(const BSDFContext& ctx, const Vec3f& wo_local) const;

    // The guide's density of a local direction (0 when not guided).
    float guide_pdf(const Vec3f& wo_local) const { return guide_ ? guide_->pdf(si_->to_world(wo_local)) : 0.f; }
    bool guided() const { return guide_ != nullptr; }
    float bsdf_probability() const { return alpha_; }

  private:
    const BSDF* bsdf_;
    const SurfaceInteraction* si_;
    const Vmm* guide_ = nullptr;
    float alpha_ = 1.f;
};

}  // namespace volguide
