#include "volguide/integrators/guided/walk/surface_vertex.h"

#include "volguide/guiding/surface_guide.h"
#include "volguide/integrators/guided/estimates/surface_leaf.h"

namespace volguide {

void SurfaceVertex::prepare(const SurfaceInteraction& si, const BSDF& bsdf, const Medium* medium) {
    sampler_.reset();
    leaf_ = -1;
    guidable_ = false;
    if (!guide_.guides_surfaces() || bsdf.is_null()) return;
    const Vmm* guide = nullptr;
    float bsdf_prob = guide_.settings().bsdf_prob;
    const GuidingField& field = guide_.field();
    if (!field.empty() && bsdf.flags() == bsdf_flags::DiffuseReflection) {
        ++counts_.surface_vertices;
        const SurfaceLeaf beside = surface_leaf(field, si);
        counts_.work.add(Work::Descent);
        leaf_ = beside.leaf;
        const Vmm* leaf = leaf_ >= 0 ? guide_.prepared().direction_vmm(leaf_) : nullptr;
        TrustPoint at{DecisionKind::Surface};
        if (leaf && medium) {  // the leaf's confidence as in the medium the path arrived through
            at.leaf = leaf_;
            at.sigma_t = medium->eval(si.p).sigma_t;
        }
        if (leaf_ >= 0)
            at.learned = guide_.allocation().share(DecisionKind::Surface, guide_.selection_cell(leaf_),
                                                   exploration_coin(si.p, si.wi, 3), learning_);
        const GuidedShare g = guide_.trust().guided_share(at);
        const bool guidable =
            leaf && g.source != ShareSource::Skipped && field.leaves()[size_t(leaf_)].mostly_medium();
        if (guidable && g.source == ShareSource::Unselected) {
            ++counts_.surface_unselected;  // only vertices the configured mixture would guide
            guidable_ = true;
        } else if (guidable) {
            bsdf_prob = 1.f - g.share;
            guide = guide_of(leaf_, beside.n);
        }
    }
    sampler_.emplace(bsdf, si, guide, bsdf_prob);
    counts_.surface_guided_vertices += sampler_->guided();
    if (sampler_->guided()) counts_.work.add(Work::SurfaceGuide);
}

const Vmm* SurfaceVertex::guide_of(int index, const Vec3f& n) {
    const Vmm& incident = *guide_.prepared().direction_vmm(index);
    if (guide_.settings().direction == DirectionGuiding::Incident) return &incident;
    return cosine_product(incident, n, product_) ? &product_ : nullptr;
}

}  // namespace volguide
