#pragma once
// The guided decisions of one medium vertex, prepared once (Open PGL's SurfaceSamplingDistribution /
// VolumeSamplingDistribution shape: Init, then Sample / PDF): init finds the vertex's kd leaf (no
// descent when the decision before handed it on in the VertexLeaf) and builds the direction mixture
// (the leaf VMM x phase product) once; the object then answers
//  - the direction decision: sample_direction / direction_pdf (the one-sample mixture of the phase
//    function and the guide, guiding/guided_direction.h);
//  - scatter_probability(w, ...): the guided volume scattering probability of the next segment in
//    direction w (docs/theory.md §7.10), from the same leaf's tables (one lookup);
//  - estimate(stage, w): the field's estimate the continuation decision reads (guided_continuation.h's
//    estimate, the same values).
// Phase sampling (and no estimate) where the field has no valid leaf or the direction is not guided.
#include <optional>

#include "volguide/guiding/guided_direction.h"
#include "volguide/integrators/guided/walk/walk_guide.h"
#include "volguide/integrators/volpath/walk_policy.h"

namespace volguide {

class GuidedVertex {
  public:
    // The guide must outlive the object; one object serves one vertex at a time (init again for the next).
    explicit GuidedVertex(const WalkGuide& guide) : guide_(guide) {}

    // Prepares the vertex mi (mi.medium set): its leaf (kept in `vertex_leaf`) and, when directions
    // are guided, the direction mixture.
    void init(const MediumInteraction& mi, VertexLeaf& vertex_leaf);
    // The vertex's kd leaf (-1: none or not known).
    int leaf() const { return leaf_; }
    // Whether init built a direction sampler (directions guided); without one the walk samples the
    // phase function itself, with its own random numbers.
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
    // segment's albedo and unguided scattering probability 1 - T (WalkGuide::guided_scatter_probability);
    // NaN where the field has nothing to say (the caller takes the unguided probability).
    float scatter_probability(const Vec3f& w, float albedo, float unguided) const;
    // The continuation's estimate for `stage` along w (guided_continuation.h); 0 without a trusted leaf.
    Color3 estimate(ContinuationStage stage, const Vec3f& w) const;

  private:
    const WalkGuide& guide_;
    MediumInteraction mi_;  // a copy: the walk's vertex may move before the decisions are made
    bool has_mi_ = false;
    int leaf_ = -1;
    std::optional<GuidedDirectionSampler> direction_;
};

}  // namespace volguide
