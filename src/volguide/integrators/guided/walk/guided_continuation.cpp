#include "volguide/integrators/guided/walk/guided_continuation.h"

#include <algorithm>
#include <limits>

namespace volguide {

Continuation GuidedContinuation::decide(ContinuationStage stage, const MediumInteraction& mi, const Vec3f& w,
                                        const Color3& throughput, int branches, float allowance, Sampler& sampler,
                                        VertexLeaf& vertex_leaf, bool report) const {
    if (rrs_ && volpath_cell(mi, vertex_leaf)) return {};  // learned: volpath's roulette, no estimate read
    if (ears_ && rrs_) return decide_ears(stage, mi, w, throughput, branches, allowance, sampler, vertex_leaf, report);
    Continuation c;
    if (!rrs_ && !report) return c;
    const Color3 estimate = this->estimate(stage, mi, w, vertex_leaf);
    const bool usable = estimate.max_value() > 0.f;
    if (report && usable) c.estimate = estimate.average();
    if (!rrs_) return c;
    if (usable && !selected(stage, vertex_leaf.leaf)) return c;  // learned: throughput RR
    c.guided = usable;
    c.q = rrs_->factor(throughput, estimate, pixel_, branches, allowance);
    draw(c, sampler);
    return c;
}

Continuation GuidedContinuation::decide_ears(ContinuationStage stage, const MediumInteraction& mi, const Vec3f& w,
                                             const Color3& throughput, int branches, float allowance,
                                             Sampler& sampler, VertexLeaf& vertex_leaf, bool report) const {
    Continuation c;
    if (vertex_leaf.leaf < 0 && leaf_hint_ >= 0) vertex_leaf.leaf = guide_.leaf_of(mi.p, VertexLeaf{leaf_hint_});
    // The field's estimate only for a recorder that reads it; either way the vertex leaf is found
    // (kept in vertex_leaf, trusted or not: the statistics are the cell's, not the field's estimate).
    if (report) {
        const Color3 estimate = this->estimate(stage, mi, w, vertex_leaf);
        if (estimate.max_value() > 0.f) c.estimate = estimate.average();
    } else {
        guide_.trusted_vertex_leaf(mi, vertex_leaf);
    }
    leaf_hint_ = vertex_leaf.leaf;
    const float q = ears_->factor(stage, guide_.selection_cell(vertex_leaf.leaf), continuation_direction_bin(w),
                                  throughput.average() / pixel_);
    const float estimate = c.estimate;
    c = ears_outcome(q, throughput, branches, allowance, sampler);
    c.estimate = estimate;
    return c;
}

Continuation GuidedContinuation::decide_surface(const SurfaceInteraction& si, const Vec3f& w, const Color3& throughput,
                                                int branches, float allowance, Sampler& sampler,
                                                VertexLeaf& leaf) const {
    if (!decides_at_surfaces()) return {};
    leaf.leaf = guide_.leaf_of(si.p, VertexLeaf{leaf_hint_});
    const float q = ears_->factor(ContinuationStage::Surface, guide_.selection_cell(leaf.leaf),
                                  continuation_direction_bin(w), throughput.average() / pixel_);
    return ears_outcome(q, throughput, branches, allowance, sampler);
}

Continuation GuidedContinuation::ears_outcome(float q, const Color3& throughput, int branches, float allowance,
                                              Sampler& sampler) const {
    Continuation c;
    if (q < 0.f) {
        rrs_->count_unlearned();
        return c;
    }
    c.guided = true;
    // Roulette never harder than the bounded throughput rule's survival min(1, max beta): the learned
    // M2 of a heavy-tailed continuation is underestimated from few samples, and ears' roulette alone
    // made paths of weight > 1 that raised the variance per sample 3-4x (docs/theory.md §9.8).
    c.q = rrs_->bound(std::max(q, std::min(1.f, throughput.max_value())), branches, allowance);
    draw(c, sampler);
    return c;
}

void GuidedContinuation::draw(Continuation& c, Sampler& sampler) const {
    if (c.q == 1.f) return;
    c.n = stochastic_round(c.q, sampler.next_1d());
    rrs_->count_outcome(c.n);
}

float GuidedContinuation::branch_budget() const {
    if (rrs_ && ears_) return ears_->branch_budget();
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

bool GuidedContinuation::volpath_cell(const MediumInteraction& mi, VertexLeaf& vertex_leaf) const {
    if (!guide_.selection().has_volpath_cells() || !mi.medium) return false;
    vertex_leaf.leaf = guide_.leaf_of(mi.p, vertex_leaf);  // finding the cell (kept for the next decision)
    return guide_.selection().volpath(guide_.selection_cell(vertex_leaf.leaf));
}

bool GuidedContinuation::selected(ContinuationStage stage, int leaf) const {
    if (guide_.selection().rrs_acts(int(stage), guide_.selection_cell(leaf))) return true;
    guide_.count_rrs_unselected();
    return false;
}

}  // namespace volguide
