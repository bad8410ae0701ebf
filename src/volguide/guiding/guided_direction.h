#pragma once
// Guided directional sampling at a medium vertex (docs/theory.md §8): a one-sample defensive mixture
//   p(wo) = alpha_f f_p(wi, wo) + (1 - alpha_f) V(wo)
// of the phase function and a guide VMM V, where V is
//   Incident: the leaf's incident-radiance VMM V_L alone;
//   Product:  V_L(wo) V_f(wo) / Z, V_f the phase function's zonal VMM (phase_vmm.h) oriented along
//             the travel direction -wi (K x J lobes, eq. 8.1); an isotropic phase gives V_L itself.
// Directions: wi = -ray.d points back where the path came from (media/phase.h); wo is the new travel
// direction, which is a direction towards the light for V_L (docs/theory.md §1.1), so the target is
// f_p(wi, wo) L(x, wo) with no sign flip on wo.
//
// The VMMs only shape probabilities: weights always use the exact phase function (§4.4). Without a
// usable guide (null / invalid / empty leaf, Phase mode, or a product whose integral is not a
// positive finite number) alpha_f is 1 and the sampler is exactly the phase function's.
// alpha_f = 0 (pure guide) is allowed for testing; rendering should keep alpha_f > 0, so that
// directions where a float vMF underflows to 0 still have a positive pdf.
//
// Cost (docs/theory.md §3.7): the leaf's mixture is read as a lobe block (vmm/lobe_block.h: float
// structure of arrays with its normalisation and sampling constant precomputed) and the phase function
// as its prepared lobes (PhaseLobes, once per medium); the product's K x J pair masses are built once,
// vectorised, at construction (vmm/lobe_product.h), and its density is evaluated in factorised form,
// V_L(wo) V_f(wo) / Z. sample() evaluates the phase function once and the guide once. Where the product
// cannot pay it is not built: a near-isotropic phase function (PhaseLobes::isotropic) guides by V_L
// alone, a near-uniform leaf (every lobe's kappa below kUniformLeafKappa) leaves the phase function
// alone (alpha_f = 1); the pdf is always the one sampled.
#include <memory>
#include <optional>

#include "volguide/guiding/guiding_field.h"
#include "volguide/media/phase.h"
#include "volguide/vmm/lobe_block.h"
#include "volguide/vmm/lobe_product.h"
#include "volguide/vmm/phase_vmm.h"

namespace volguide {

enum class DirectionGuiding { Phase, Incident, Product };

class GuidedDirectionSampler {
  public:
    static constexpr float kDefaultPhaseProbability = 0.5f;  // Open PGL's phaseFunctionProbability
    // A leaf whose every lobe is below this concentration is near-uniform (its density varies by
    // < 2 % over the sphere): the product would be the phase function, so the phase function samples.
    static constexpr float kUniformLeafKappa = 0.01f;

    // The render's form: `leaf` the leaf's block (empty: no usable leaf), `lobes` the phase function's
    // prepared lobes (Product mode only); both, and `phase`, must outlive the sampler. `phase_prob` =
    // alpha_f, clamped to [0, 1] (NaN: 1).
    GuidedDirectionSampler(DirectionGuiding mode, const LobeBlock& leaf, const PhaseFunction& phase,
                           const PhaseLobes& lobes, const Vec3f& wi, float phase_prob = kDefaultPhaseProbability);
    // The library's form: a field leaf (may be null; its `vmm` guides where `valid`), copied into the
    // sampler's own block. `phase_vmm`: the zonal VMM of `phase` (e.g. hg_phase_vmm(g)); null computes
    // hg_phase_vmm(phase.mean_cosine()) here.
    GuidedDirectionSampler(DirectionGuiding mode, const GuidingLeaf* leaf, const PhaseFunction& phase,
                           const Vec3f& wi, float phase_prob = kDefaultPhaseProbability,
                           const PhaseVmm* phase_vmm = nullptr);

    struct Sample {
        Vec3f wo;
        float pdf = 0.f;      // full mixture pdf p(wo); 0 marks a failed sample (weight 0)
        float phase = 0.f;    // f_p(wi, wo), exact
        float weight = 0.f;   // f_p / pdf
        bool guided = false;  // drawn from the guide VMM (false: from the phase function)
    };
    // Random numbers: u_strategy < alpha_f picks the phase function, otherwise the guide; `u`
    // then drives the chosen sampler (the guide reuses u.x for its lobe choice). Three dimensions.
    Sample sample(Point2f u, float u_strategy) const;

    // The full one-sample mixture pdf alpha_f f_p + (1 - alpha_f) V (what MIS with NEE must use).
    float pdf(const Vec3f& wo) const;
    // f_p(wi, wo) exactly (never the VMM fit).
    float eval_phase(const Vec3f& wo) const { return phase_->eval(wi_, wo); }
    // V(wo), the guide alone (0 when not guided).
    float guide_pdf(const Vec3f& wo) const;

    // True when the guide takes part (alpha_f < 1); false: pure phase sampling.
    bool guided() const { return guide_ != Guide::None; }
    DirectionGuiding mode() const { return mode_; }
    float phase_probability() const { return alpha_; }
    // Product mode: Z = integral of V_L V_f over the sphere, so Phi Z is the leaf's in-scattered
    // radiance estimate for this vertex (docs/theory.md §5.6); 0 otherwise.
    double product_integral() const { return guide_ == Guide::Product ? product_.integral() : product_integral_; }
    // The product guide; null unless guiding by a product (a near-isotropic phase guides by V_L itself).
    const LobeProduct* product() const { return guide_ == Guide::Product ? &product_ : nullptr; }

  private:
    enum class Guide { None, Leaf, Product };
    // The library form's copies (the render's form reads the caller's).
    struct Owned {
        alignas(64) std::array<float, kLobeArrays * kVmmMaxLobes> block;
        PhaseLobes lobes;
    };
    void init(const LobeBlock& leaf, const PhaseLobes* lobes, float phase_prob);
    // Draws from the guide (Leaf: a lobe by weight, Product: a pair by mass).
    Vec3f sample_guide(Point2f u) const;

    DirectionGuiding mode_;
    const PhaseFunction* phase_;
    Vec3f wi_;
    float alpha_ = 1.f;
    Guide guide_ = Guide::None;
    LobeBlock leaf_;
    double product_integral_ = 0.0;
    LobeProduct product_;  // Guide::Product (only its used pairs are written)
    std::shared_ptr<Owned> owned_;  // shared by copies (a split path's copies share their vertex's sampler)
};

}  // namespace volguide
