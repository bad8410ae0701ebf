#include "volguide/guiding/guided_direction.h"

#include <algorithm>
#include <cmath>

namespace volguide {

namespace {

// Whether every lobe of the block is near-uniform (GuidedDirectionSampler::kUniformLeafKappa).
bool near_uniform(const LobeBlock& b) {
    for (int k = 0; k < b.count; ++k)
        if (!(b.kappa()[k] < GuidedDirectionSampler::kUniformLeafKappa)) return false;
    return true;
}

// The lobe u.x picks by weight (u.x rescaled to [0, 1)), as VmfMixture::select_lobe.
int select_lobe(const LobeBlock& b, float& u) {
    for (int k = 0; k + 1 < b.count; ++k) {
        const float w = b.weight()[k];
        if (u < w) {
            u = std::min(u / w, OneMinusEpsilon);
            return k;
        }
        u -= w;
    }
    const int last = b.count - 1;
    const float w = b.weight()[last];
    u = w > 0.f ? std::clamp(u / w, 0.f, OneMinusEpsilon) : 0.f;
    return last;
}

}  // namespace

GuidedDirectionSampler::GuidedDirectionSampler(DirectionGuiding mode, const LobeBlock& leaf,
                                               const PhaseFunction& phase, const PhaseLobes& lobes, const Vec3f& wi,
                                               float phase_prob)
    : mode_(mode), phase_(&phase), wi_(wi) {
    init(leaf, &lobes, phase_prob);
}

GuidedDirectionSampler::GuidedDirectionSampler(DirectionGuiding mode, const GuidingLeaf* leaf,
                                               const PhaseFunction& phase, const Vec3f& wi, float phase_prob,
                                               const PhaseVmm* phase_vmm)
    : mode_(mode), phase_(&phase), wi_(wi) {
    LobeBlock block;
    if (mode != DirectionGuiding::Phase && leaf && leaf->valid && leaf->vmm.weight_sum() > 0.0) {
        owned_ = std::make_shared<Owned>();
        block = write_lobe_block(leaf->vmm, owned_->block.data());
        owned_->lobes = prepare_phase_lobes(phase_vmm ? *phase_vmm : hg_phase_vmm(phase.mean_cosine()));
    }
    init(block, owned_ ? &owned_->lobes : nullptr, phase_prob);
}

void GuidedDirectionSampler::init(const LobeBlock& leaf, const PhaseLobes* lobes, float phase_prob) {
    const float alpha = std::isnan(phase_prob) ? 1.f : std::clamp(phase_prob, 0.f, 1.f);  // NaN: phase only
    if (mode_ == DirectionGuiding::Phase || alpha >= 1.f || leaf.empty()) return;
    leaf_ = leaf;
    if (mode_ == DirectionGuiding::Incident || lobes->isotropic()) {
        // The leaf's mixture itself (a near-isotropic phase factor is a constant: V_L / 4 pi normalised
        // is V_L, Z = 1 / 4 pi for a normalised mixture).
        guide_ = Guide::Leaf;
        if (mode_ == DirectionGuiding::Product) product_integral_ = double(InvFourPi);
    } else {
        if (near_uniform(leaf)) return;  // the product is the phase function: phase only
        // The phase lobes sit on +-(travel direction) = +-(-wi) (phase_vmm.h).
        if (!product_.build(leaf, *lobes, -wi_)) return;  // nothing to guide with: phase only
        guide_ = Guide::Product;
    }
    alpha_ = alpha;
}

float GuidedDirectionSampler::guide_pdf(const Vec3f& wo) const {
    switch (guide_) {
        case Guide::Leaf:
            return lobe_block_eval(leaf_, wo).value();
        case Guide::Product:
            return product_.pdf(wo);
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

Vec3f GuidedDirectionSampler::sample_guide(Point2f u) const {
    if (guide_ == Guide::Product) return product_.sample(u);
    const int k = select_lobe(leaf_, u.x);
    const Vec3f mu(leaf_.mu_x()[k], leaf_.mu_y()[k], leaf_.mu_z()[k]);
    return sample_vmf_prepared(mu, leaf_.kappa()[k], leaf_.expm1()[k], u);
}

GuidedDirectionSampler::Sample GuidedDirectionSampler::sample(Point2f u, float u_strategy) const {
    Sample s;
    float phase_pdf;
    if (guide_ == Guide::None || u_strategy < alpha_) {
        // The phase function's own sample carries its value and pdf: nothing evaluated again.
        const PhaseSample ps = phase_->sample(wi_, u);
        s.wo = ps.wo;
        phase_pdf = ps.pdf;
        s.phase = ps.pdf > 0.f ? ps.weight * ps.pdf : 0.f;
        if (guide_ == Guide::None) {
            s.pdf = ps.pdf;
            s.weight = ps.weight;
            return s;
        }
    } else {
        s.wo = sample_guide(u);
        s.guided = true;
        const PhaseValue v = phase_->eval_pdf(wi_, s.wo);
        s.phase = v.value;
        phase_pdf = v.pdf;
    }
    s.pdf = (alpha_ > 0.f ? alpha_ * phase_pdf : 0.f) + (1.f - alpha_) * guide_pdf(s.wo);
    // A direction where every term underflowed (only possible with alpha_f = 0) is a failed sample.
    s.weight = s.pdf > 0.f ? s.phase / s.pdf : 0.f;
    if (!(s.pdf > 0.f)) s.pdf = 0.f;
    return s;
}

}  // namespace volguide
