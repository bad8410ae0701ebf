#pragma once
// Guided Russian roulette and splitting's decision at a medium vertex (docs/theory.md §9.3), made here
// and nowhere else: volpath's walk asks its policy for a continuation once per vertex stage
// (walk_policy.h's ContinuationStage) and GuidedWalkPolicy forwards to this class with its vertex
// object (GuidedVertex, guided_vertex.h), whose leaf and estimate the decision reads:
//  - the field's estimate for the stage (GuidedVertex::estimate): L~_i(x, d) after the distance
//    decision (what the vertex collects from here on, d the ray's direction), L~(x, w) after the
//    direction decision (what the continuation along w collects), 0 (no guided decision: throughput
//    RR) where the field has no valid leaf, and where the leaf's confidence is below WalkGuide's
//    skip threshold: deep in a dense medium one estimate per leaf cannot follow radiance that varies
//    on the scale of a free path, and RR by it compounds into heavy-tailed weights from leaves
//    estimated too dark;
//  - the pixel estimate I of the camera sample's pixel (estimates/pixel_estimate.h);
// and hands them to RouletteSplitting's scene-free weight window (guiding/roulette_splitting.h):
// its factor q, the number of continuations n drawn from it, and the outcome's count. The walk
// applies the result: the path's weight 1/q and its copies (VolumeWalk::continue_path).
//
// rrs=ears (docs/theory.md §9.8) decides instead from the learned statistics of the pass's frozen
// ContinuationSnapshot (estimates/continuation_snapshot.h): the factor of the vertex leaf's cell and the
// direction bin of w, with the path's weight relative to I; RouletteSplitting bounds it. Where the
// statistics are too few there is no decision (the walk's throughput roulette, rr_rule=bounded by
// default with ears).
#include "volguide/core/color.h"
#include "volguide/core/sampler.h"
#include "volguide/geometry/interaction.h"
#include "volguide/guiding/roulette_splitting.h"
#include "volguide/integrators/guided/estimates/continuation_snapshot.h"
#include "volguide/integrators/guided/walk/guided_vertex.h"
#include "volguide/integrators/guided/walk/walk_guide.h"
#include "volguide/integrators/volpath/walk_policy.h"

namespace volguide {

class GuidedContinuation {
  public:
    // `rrs` null: no guided RR/splitting; `pixel`: I of the camera sample's pixel (> 0 with rrs);
    // `ears`: the pass's statistics (required with rrs=ears).
    GuidedContinuation(const WalkGuide& guide, const RouletteSplitting* rrs, float pixel,
                       const ContinuationSnapshot* ears = nullptr)
        : guide_(guide), rrs_(rrs), pixel_(pixel), ears_(ears) {}

    // WalkPolicy::continuation's decision of `query` at `vertex`. Without rrs it decides nothing;
    // query.report still reads the estimate and returns it in Continuation::estimate.
    // Continuation::leaf: the vertex's leaf where the decision read it (-1 otherwise).
    Continuation decide(const ContinuationQuery& query, GuidedVertex& vertex, Sampler& sampler) const;
    // rrs=ears's decision after the BSDF sampled the diffuse direction query.w at the surface vertex si,
    // from the statistics of the surface's leaf (found with the guess `hint`, returned in
    // Continuation::leaf); no decision (q = 1) without ears.
    Continuation decide_surface(const SurfaceInteraction& si, const ContinuationQuery& query, Sampler& sampler,
                                int hint) const;
    bool decides_at_surfaces() const { return ears_ && rrs_; }
    // Whether the walk's camera sample is recorded for the allocation's learning (it explores then).
    void set_learning(bool learning) { learning_ = learning; }
    // The camera sample's branch allowance (+inf without a budget or without rrs).
    float branch_budget() const;
    // Counts a finished camera sample's branches.
    void end_camera_sample(int branches) const;

  private:
    // rrs=ears's decision (decide()'s arguments).
    Continuation decide_ears(const ContinuationQuery& query, GuidedVertex& vertex, Sampler& sampler) const;
    // The decision of `query` from ears' factor q (< 0: too few statistics, no decision): bounded, then
    // drawn.
    Continuation ears_outcome(float q, const ContinuationQuery& query, Sampler& sampler) const;
    // A roulette factor q < 1 raised to the bounded throughput rule's survival `bound` (splitting
    // unchanged).
    static float bounded_roulette(float q, float bound);
    // The allocation's continuation rule at `vertex` for `query`.
    ContinuationRule rule(const ContinuationQuery& query, GuidedVertex& vertex) const;
    // Draws n from c.q (q != 1) and counts the outcome.
    void draw(Continuation& c, Sampler& sampler) const;
    const WalkGuide& guide_;
    const RouletteSplitting* rrs_;
    float pixel_;
    const ContinuationSnapshot* ears_;
    bool learning_ = false;
};

}  // namespace volguide
