#include "volguide/integrators/guided/walk/guided_vertex.h"

namespace volguide {

void GuidedVertex::init(const MediumInteraction& mi, const VertexLeaf& handed) {
    clear();
    mi_ = mi;
    active_ = true;
    known_ = handed.leaf;
    guide_.count_vertex();
}

void GuidedVertex::clear() {
    if (found_valid_ && found_ >= 0) hint_ = found_;
    active_ = false;
    known_ = -1;
    found_valid_ = false;
    prepared_ = false;
    direction_.reset();
}

int GuidedVertex::find() {
    if (!found_valid_) {
        found_ = guide_.vertex_leaf_of(mi_.p, known_ >= 0 ? known_ : hint_);
        found_valid_ = true;
    }
    return found_;
}

int GuidedVertex::leaf() {
    const int l = find();
    if (l >= 0) known_ = l;  // the decisions that follow at this vertex know it
    return l;
}

int GuidedVertex::trusted_leaf() { return guide_.trusted_leaf(leaf(), mi_.coeffs.sigma_t); }

void GuidedVertex::prepare_direction() {
    if (prepared_) return;
    prepared_ = true;
    if (!guide_.guides_direction()) return;
    guide_.direction_sampler(mi_, mi_.medium->phase(), leaf(), direction_);
    guide_.count_vertex_mixture(direction_ && direction_->product() != nullptr);
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

float GuidedVertex::scatter_probability(const Vec3f& w, float albedo, float unguided) {
    return guide_.guided_scatter_probability(origin_leaf(), mi_.medium->phase(), w, albedo, unguided);
}

Color3 GuidedVertex::estimate(ContinuationStage stage, const Vec3f& w) {
    const int leaf = trusted_leaf();
    if (leaf < 0) return Color3(0.f);
    const PhaseFunction& phase = mi_.medium->phase();
    // After the direction decision the full L~, although NEE took the direct light at x: the
    // continuation still collects the emitter hits MIS gives it (a sky), and the indirect part
    // alone under-estimated it.
    return stage == ContinuationStage::Distance ? guide_.leaf_inscattered(leaf, phase, w)
                                                : guide_.leaf_incident(leaf, phase, w);
}

}  // namespace volguide
