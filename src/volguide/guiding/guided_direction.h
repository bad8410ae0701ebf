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
// Cost: the product is built once at construction into fixed storage (no heap allocation);
// sample() and pdf() evaluate the phase function and the guide's lobes once each.
#include <optional>

#include "volguide/guiding/guiding_field.h"
#include "volguide/media/phase.h"
#include "volguide/vmm/phase_vmm.h"

namespace volguide {

enum class DirectionGuiding { Phase, Incident, Product };

class GuidedDirectionSampler {
  public:
    // Radiance VMM x phase VMM: room for the largest leaf mixture times the largest phase fit.
    using ProductVmm = VmfMixture<kVmmMaxLobes * kPhaseVmmMaxLobes>;
    static constexpr float kDefaultPhaseProbability = 0.5f;  // Open PGL's phaseFunctionProbability

    // `phase` and `leaf` (may be null) must outlive the sampler. `phase_prob` = alpha_f, clamped
    // to [0, 1] (NaN: 1).
    // `phase_vmm`: the zonal VMM of `phase` (e.g. hg_phase_vmm(g), prepared once per medium by the
    // caller); null computes hg_phase_vmm(phase.mean_cosine()) here (a table lookup and J
    // A3-inversions). Only Product mode reads it.
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
    double product_integral() const { return product_integral_; }
    // The product guide VMM; null unless guiding by a product (g = 0 guides by V_L itself).
    const ProductVmm* product() const { return guide_ == Guide::Product ? &*product_ : nullptr; }

  private:
    enum class Guide { None, Leaf, Product };

    DirectionGuiding mode_;
    const PhaseFunction* phase_;
    Vec3f wi_;
    float alpha_ = 1.f;
    Guide guide_ = Guide::None;
    const Vmm* leaf_vmm_ = nullptr;  // Guide::Leaf
    double product_integral_ = 0.0;
    std::optional<ProductVmm> product_;  // Guide::Product (3 KB, only built when used)
};

}  // namespace volguide
