#include "volguide/guiding/guided_direction.h"

#include <algorithm>
#include <cmath>

#include "volguide/vmm/vmm_fast_product.h"

namespace volguide {

namespace {

// A leaf whose VMM has mass (a normalised VMM's weights sum to 1).
bool usable(const GuidingLeaf* leaf) {
    return leaf && leaf->valid && leaf->vmm.weight_sum() > 0.0;
}

// One lobe of concentration ~0: the phase VMM of an isotropic phase function.
bool is_uniform(const PhaseVmm& phase) {
    return phase.count == 1 && phase.kappa[0] < kVmfUniformKappa;
}

}  // namespace

GuidedDirectionSampler::GuidedDirectionSampler(DirectionGuiding mode, const GuidingLeaf* leaf,
                                               const PhaseFunction& phase, const Vec3f& wi, float phase_prob,
                                               const PhaseVmm* phase_vmm)
    : mode_(mode), phase_(&phase), wi_(wi) {
    const float alpha = std::isnan(phase_prob) ? 1.f : std::clamp(phase_prob, 0.f, 1.f);  // NaN: phase only
    if (mode == DirectionGuiding::Phase || alpha >= 1.f || !usable(leaf)) return;

    if (mode == DirectionGuiding::Incident) {
        guide_ = Guide::Leaf;
        leaf_vmm_ = &leaf->vmm;
    } else {
        const PhaseVmm own = phase_vmm ? PhaseVmm{} : hg_phase_vmm(phase.mean_cosine());
        const PhaseVmm& fp = phase_vmm ? *phase_vmm : own;
        if (is_uniform(fp)) {
            // V_L (1 / 4 pi) normalised is V_L; Z = (weight sum) / 4 pi.
            guide_ = Guide::Leaf;
            leaf_vmm_ = &leaf->vmm;
            product_integral_ = leaf->vmm.weight_sum() * double(InvFourPi);
        } else {
            // The phase VMM's lobes sit on +-(travel direction) = +-(-wi) (phase_vmm.h).
            product_integral_ = product_fast(leaf->vmm, fp.oriented(-wi), product_.emplace(ProductVmm::Uninitialized{}));
            if (!(product_integral_ > 0.0) || !std::isfinite(product_integral_) || product_->count == 0) {
                product_.reset();
                product_integral_ = 0.0;
                return;  // nothing to guide with: phase only
            }
            guide_ = Guide::Product;
        }
    }
    alpha_ = alpha;
}

float GuidedDirectionSampler::guide_pdf(const Vec3f& wo) const {
    switch (guide_) {
        case Guide::Leaf:
            return leaf_vmm_->pdf(wo);
        case Guide::Product:
            return product_->pdf(wo);
        case Guide::None:
            break;
    }
    return 0.f;
}

float GuidedDirectionSampler::pdf(const Vec3f& wo) const {
    if (guide_ == Guide::None) return phase_->pdf(wi_, wo);
    const float phase_part = alpha_ > 0.f ? alpha_ * phase_->pdf(wi_, wo) : 0.f;
    return phase_part + (1.f - alpha_) * guide_pdf(wo);
}

GuidedDirectionSampler::Sample GuidedDirectionSampler::sample(Point2f u, float u_strategy) const {
    Sample s;
    if (guide_ == Guide::None) {
        const PhaseSample ps = phase_->sample(wi_, u);
        s.wo = ps.wo;
        s.pdf = ps.pdf;
        s.weight = ps.weight;
        s.phase = ps.weight * ps.pdf;
        return s;
    }
    if (u_strategy < alpha_) {
        s.wo = phase_->sample(wi_, u).wo;
    } else {
        s.wo = guide_ == Guide::Leaf ? leaf_vmm_->sample(u) : product_->sample(u);
        s.guided = true;
    }
    s.phase = eval_phase(s.wo);
    s.pdf = pdf(s.wo);
    // A direction where every term underflowed (only possible with alpha_f = 0) is a failed sample.
    s.weight = s.pdf > 0.f ? s.phase / s.pdf : 0.f;
    if (!(s.pdf > 0.f)) s.pdf = 0.f;
    return s;
}

}  // namespace volguide
