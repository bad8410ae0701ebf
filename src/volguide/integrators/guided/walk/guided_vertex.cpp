#include "volguide/integrators/guided/walk/guided_vertex.h"

#include <limits>

namespace volguide {

void GuidedVertex::init(const MediumInteraction& mi, VertexLeaf& vertex_leaf) {
    mi_ = mi;
    has_mi_ = true;
    direction_.reset();
    if (guide_.guides_direction()) guide_.direction_sampler(mi, mi.medium->phase(), vertex_leaf, direction_);
    leaf_ = vertex_leaf.leaf;
}

GuidedDirectionSampler::Sample GuidedVertex::sample_direction(Point2f u, float u_strategy) const {
    if (direction_) return direction_->sample(u, u_strategy);
    // Not guided: the phase function (the walk without a guide draws the same numbers as phase().sample).
    const PhaseSample ps = mi_.medium->phase().sample(mi_.wi, u);
    GuidedDirectionSampler::Sample s;
    s.wo = ps.wo;
    s.pdf = ps.pdf;
    s.weight = ps.weight;
    s.phase = ps.pdf > 0.f ? ps.weight * ps.pdf : 0.f;
    return s;
}

float GuidedVertex::direction_pdf(const Vec3f& wo) const {
    return direction_ ? direction_->pdf(wo) : mi_.medium->phase().pdf(mi_.wi, wo);
}

float GuidedVertex::scatter_probability(const Vec3f& w, float albedo, float unguided) const {
    if (!has_mi_) return std::numeric_limits<float>::quiet_NaN();
    VertexLeaf vl{leaf_};
    const int leaf = guide_.trusted_vertex_leaf(mi_, vl);
    return guide_.guided_scatter_probability(leaf, mi_.medium->phase(), w, albedo, unguided);
}

Color3 GuidedVertex::estimate(ContinuationStage stage, const Vec3f& w) const {
    if (!has_mi_ || !mi_.medium) return Color3(0.f);
    VertexLeaf vl{leaf_};
    const int leaf = guide_.trusted_vertex_leaf(mi_, vl);
    if (leaf < 0) return Color3(0.f);
    const PhaseFunction& phase = mi_.medium->phase();
    return stage == ContinuationStage::Distance ? guide_.leaf_inscattered(leaf, phase, w)
                                                : guide_.leaf_incident(leaf, phase, w);
}

}  // namespace volguide
