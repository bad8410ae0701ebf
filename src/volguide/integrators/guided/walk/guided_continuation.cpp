#include "volguide/integrators/guided/walk/guided_continuation.h"

#include <algorithm>
#include <limits>

namespace volguide {

ContinuationRule GuidedContinuation::rule(const ContinuationQuery& query, GuidedVertex& vertex) const {
    const Allocation& allocation = guide_.allocation();
    if (allocation.empty()) return ContinuationRule::Splitting;
    const MediumInteraction& mi = vertex.interaction();
    return allocation.rule(guide_.selection_cell(vertex.leaf()),
                           exploration_coin(mi.p, query.w, 4 + uint64_t(query.stage)), learning_);
}

Continuation GuidedContinuation::decide(const ContinuationQuery& query, GuidedVertex& vertex, Sampler& sampler) const {
    if (ears_ && rrs_) return decide_ears(query, vertex, sampler);
    Continuation c;
    c.q_unguided = query.roulette;
    const ContinuationRule chosen = rrs_ ? rule(query, vertex) : ContinuationRule::Unguided;
    if (chosen == ContinuationRule::Unguided) {  // the walk's roulette: nothing read, nothing drawn
        c.leaf = vertex.leaf();
        return c;
    }
    const Color3 estimate = vertex.estimate(query.stage, query.w);
    const bool usable = estimate.max_value() > 0.f;
    if (query.report && usable) c.estimate = estimate.average();
    const float q = bounded_roulette(rrs_->factor(query.throughput, estimate, pixel_, query.branches, query.allowance),
                                     query.bound);
    // Without a usable estimate the guided rule is the walk's roulette.
    c.q_guided = usable ? q : query.roulette;
    c.q = chosen == ContinuationRule::Roulette ? std::min(q, 1.f) : q;
    // A usable estimate replaces the walk's throughput roulette at this depth, inside the weight
    // window (q = 1) too: on backlit the throughput roulette there killed the guided paths toward
    // the light (small weight, large estimate; bench/RESULTS.md, issue 55).
    c.guided = usable;
    draw(c, sampler);
    c.leaf = vertex.leaf();
    return c;
}

Continuation GuidedContinuation::decide_ears(const ContinuationQuery& query, GuidedVertex& vertex,
                                             Sampler& sampler) const {
    // The field's estimate only for a recorder that reads it; either way the vertex leaf is found
    // (trusted or not: the statistics are the cell's, not the field's estimate).
    float estimate = 0.f;
    if (query.report) {
        const Color3 e = vertex.estimate(query.stage, query.w);
        if (e.max_value() > 0.f) estimate = e.average();
    }
    const int leaf = vertex.leaf();
    const float q = ears_->factor(query.stage, guide_.selection_cell(leaf), continuation_direction_bin(query.w),
                                  query.throughput.average() / pixel_);
    Continuation c = ears_outcome(q, query, sampler);
    c.estimate = estimate;
    c.leaf = leaf;
    return c;
}

Continuation GuidedContinuation::decide_surface(const SurfaceInteraction& si, const ContinuationQuery& query,
                                                Sampler& sampler, int hint) const {
    if (!decides_at_surfaces()) return {};
    uint64_t descents = 0;  // a surface's lookup, not a vertex's descent
    const int leaf = guide_.prepared().leaf_at(si.p, hint, descents);
    const float q = ears_->factor(ContinuationStage::Surface, guide_.selection_cell(leaf),
                                  continuation_direction_bin(query.w), query.throughput.average() / pixel_);
    Continuation c = ears_outcome(q, query, sampler);
    c.leaf = leaf;
    return c;
}

Continuation GuidedContinuation::ears_outcome(float q, const ContinuationQuery& query, Sampler& sampler) const {
    Continuation c;
    if (q < 0.f) {
        rrs_->count_unlearned();
        return c;
    }
    c.guided = true;
    c.q = rrs_->bound(bounded_roulette(q, query.bound), query.branches, query.allowance);
    draw(c, sampler);
    return c;
}

// Roulette never harder than the bounded throughput rule's survival min(1, max beta eta^2) (the walk's,
// ContinuationQuery::bound: inside a refracting boundary the radiance scale eta^2 is in it): ears' learned
// M2 of a heavy-tailed continuation is underestimated from few samples, and its roulette alone made paths
// of weight > 1 that raised the variance per sample (docs/theory.md §9.8); for grrs the same bound keeps a
// survivor's weight at most the bounded rule's wherever beta eta^2 <= 1, whatever the estimates say. Only
// q changes: unbiased.
float GuidedContinuation::bounded_roulette(float q, float bound) { return q < 1.f ? std::max(q, bound) : q; }

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

}  // namespace volguide
