#include "volguide/integrators/guided/walk/guided_continuation.h"

#include <limits>

namespace volguide {

Continuation GuidedContinuation::decide(ContinuationStage stage, const MediumInteraction& mi, const Vec3f& w,
                                        const Color3& throughput, int branches, float allowance, Sampler& sampler,
                                        VertexLeaf& vertex_leaf, bool report) const {
    Continuation c;
    if (!rrs_ && !report) return c;
    const Color3 estimate = this->estimate(stage, mi, w, vertex_leaf);
    const bool usable = estimate.max_value() > 0.f;
    if (report && usable) c.estimate = estimate.average();
    if (!rrs_) return c;
    if (usable && !selected(stage, vertex_leaf.leaf)) return c;  // learned: throughput RR
    c.guided = usable;
    c.q = rrs_->factor(throughput, estimate, pixel_, branches, allowance);
    if (c.q == 1.f) return c;
    c.n = stochastic_round(c.q, sampler.next_1d());
    rrs_->count_outcome(c.n);
    return c;
}

float GuidedContinuation::branch_budget() const {
    return rrs_ ? rrs_->initial_allowance() : std::numeric_limits<float>::infinity();
}

void GuidedContinuation::end_camera_sample(int branches) const {
    if (rrs_) rrs_->count_camera_sample(branches);
}

Color3 GuidedContinuation::estimate(ContinuationStage stage, const MediumInteraction& mi, const Vec3f& w,
                                    VertexLeaf& vertex_leaf) const {
    const int leaf = mi.medium ? guide_.trusted_vertex_leaf(mi, vertex_leaf) : -1;
    if (leaf < 0) return Color3(0.f);
    const PhaseFunction& phase = mi.medium->phase();
    // After the direction decision the full L~, although NEE took the direct light at x: the
    // continuation still collects the emitter hits MIS gives it (a sky), and the indirect part
    // alone under-estimated it.
    return stage == ContinuationStage::Distance ? guide_.leaf_inscattered(leaf, phase, w)
                                                : guide_.leaf_incident(leaf, phase, w);
}

bool GuidedContinuation::selected(ContinuationStage stage, int leaf) const {
    if (guide_.selection().rrs_acts(int(stage), guide_.selection_cell(leaf))) return true;
    guide_.count_rrs_unselected();
    return false;
}

}  // namespace volguide
