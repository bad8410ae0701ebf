#pragma once
// The guided decisions of one medium vertex (Open PGL's SurfaceSamplingDistribution /
// VolumeSamplingDistribution shape: Init, then Sample / PDF), one object per vertex owned by
// GuidedWalkPolicy, which begins it when the walk reaches a vertex (before the distance-stage
// continuation decision) and ends it when the path's ray leaves from no medium vertex. Lazy:
//  - init keeps the vertex and the leaf the distance decision handed on, and looks nothing up;
//  - the vertex's kd leaf is found on the first question that needs it (one descent at most per
//    object, none when the handed leaf or the last vertex's leaf holds the point);
//  - the direction mixture (the leaf VMM x phase product, guiding/guided_direction.h) is built on
//    the first direction call (prepare_direction), so that a vertex whose path the distance-stage
//    continuation ends never builds one.
// The object then answers
//  - the direction decision: sample_direction / direction_pdf (the one-sample mixture of the phase
//    function and the guide);
//  - scatter_probability(w, ...): the guided volume scattering probability of the next segment,
//    leaving the vertex along w (docs/theory.md §7.10), from the leaf's tables (one table read);
//  - estimate(stage, w): the field's estimate the continuation decision reads (guided_continuation.h).
// Phase sampling (and no estimate) where the field has no valid leaf or the direction is not guided.
// WalkGuide's --stats counters guided_vertices / guided_vertex_descents / guided_vertex_mixtures /
// guided_vertex_products count the objects begun and what they built.
//
// Two leaves are kept apart on purpose: known_leaf() is the leaf as the decisions before knew it
// (the handed one, or the one a decision at this vertex found): the next distance decision skips
// the guided walk from a known leaf of low confidence, and a leaf found only for that decision does
// not count as known (WalkGuide::sample_distance), exactly as before the object existed, so that the
// images are unchanged. leaf() is the leaf at the point, found once.
#include <optional>

#include "volguide/guiding/guided_direction.h"
#include "volguide/integrators/guided/walk/walk_guide.h"
#include "volguide/integrators/volpath/walk_policy.h"

namespace volguide {

class GuidedVertex {
  public:
    // The guide must outlive the object; one object serves one vertex at a time (init again for the next).
    explicit GuidedVertex(const WalkGuide& guide) : guide_(guide) {}

    // Begins the vertex mi (mi.medium set); `handed`: the leaf the distance decision that reached it
    // handed on (-1: not known). Looks nothing up.
    void init(const MediumInteraction& mi, const VertexLeaf& handed);
    // No vertex (the path's ray leaves from the camera or a surface). The last leaf found stays a hint.
    void clear();
    bool active() const { return active_; }
    const MediumInteraction& interaction() const { return mi_; }

    // The leaf as the decisions made at this vertex so far know it, without a lookup (-1: not known).
    int known_leaf() const { return known_; }
    // The vertex's kd leaf (-1: outside the field), found on the first call; it becomes known.
    int leaf();
    // leaf() where its confidence at the vertex is at least WalkGuide's skip threshold, else -1.
    int trusted_leaf();
    // The leaf the next segment's distance decision starts from: the known one, else leaf() (found
    // for the decision, not made known: see the header comment).
    int origin_leaf() { return known_ >= 0 ? known_ : find(); }
    // A guess for a point near the last vertex (-1: none): the last leaf found, for leaf_of.
    int hint() const { return hint_; }

    // Builds the direction mixture on the first call (nothing when directions are not guided).
    void prepare_direction();
    // Whether prepare_direction built a direction sampler (directions guided); without one the walk
    // samples the phase function itself, with its own random numbers.
    bool has_direction_sampler() const { return direction_.has_value(); }
    // Whether the direction decision draws from a guided mixture.
    bool guided() const { return direction_ && direction_->guided(); }
    // The direction decision: u_strategy picks phase or guide, u drives it (GuidedDirectionSampler::sample).
    GuidedDirectionSampler::Sample sample_direction(Point2f u, float u_strategy) const;
    // The mixture's density (what NEE's MIS uses); the phase function's where not guided.
    float direction_pdf(const Vec3f& wo) const;
    // The guide's density alone (0 where not guided).
    float guide_pdf(const Vec3f& wo) const { return direction_ ? direction_->guide_pdf(wo) : 0.f; }

    // The guided scattering probability of the segment leaving the vertex along w, given the
    // segment's albedo and unguided scattering probability 1 - T (WalkGuide::guided_scatter_probability),
    // from origin_leaf(); NaN where the field has nothing to say (the caller takes the unguided one).
    float scatter_probability(const Vec3f& w, float albedo, float unguided);
    // The continuation's estimate for `stage` along w (guided_continuation.h) from trusted_leaf();
    // 0 without one.
    Color3 estimate(ContinuationStage stage, const Vec3f& w);

  private:
    // The leaf at the point, found once (the handed leaf, else the hint, tried before a descent).
    int find();

    const WalkGuide& guide_;
    MediumInteraction mi_;  // a copy: the walk's vertex may move before the decisions are made
    bool active_ = false;
    int known_ = -1;        // known_leaf()
    int found_ = -1;        // find()'s leaf, when found_valid_
    bool found_valid_ = false;
    int hint_ = -1;
    bool prepared_ = false;  // prepare_direction ran for this vertex
    std::optional<GuidedDirectionSampler> direction_;
};

}  // namespace volguide
