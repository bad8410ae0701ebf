#pragma once
// The guided decisions of the point a path's ray leaves from (Open PGL's SurfaceSamplingDistribution /
// VolumeSamplingDistribution shape: Init, then Sample / PDF): a medium vertex between init() and
// clear(), otherwise the camera or a surface (no vertex). One object per walk, owned by
// GuidedWalkPolicy, which begins it when the walk reaches a medium vertex (before the distance-stage
// continuation decision) and clears it when the path's ray leaves from no medium vertex. It answers
//  - the distance decision of the segment leaving it (sample_distance: the configured member of the
//    distance family, distance_sampler.h, or free flight where guiding cannot pay), for camera and
//    surface segments too;
//  - the direction decision: prepare_direction, then sample_direction / direction_pdf (the one-sample
//    mixture of the phase function and the guide, guiding/guided_direction.h);
//  - estimate(stage, w): the field's estimate the continuation decision reads (guided_continuation.h).
// Lazy: init keeps the vertex and the leaf the distance decision that reached it found (this object's
// own last decision) and looks nothing up; the vertex's leaf (leaf()) is found on the first question
// that needs it (at most one descent, none when that leaf or the last vertex's leaf holds the point);
// how much every decision follows the guide is the trust rule's (trust.h); the direction mixture
// is built on the first direction call, so a vertex whose path the distance-stage continuation ends
// never builds one. Phase sampling (and no estimate) where the field has no valid leaf or the
// direction is not guided.
#include <optional>
#include <vector>

#include "volguide/guiding/guided_direction.h"
#include "volguide/integrators/guided/walk/distance_sampler.h"
#include "volguide/integrators/guided/walk/walk_guide.h"
#include "volguide/integrators/volpath/walk_policy.h"

namespace volguide {

class GuidedVertex {
  public:
    // The guide must outlive the object, `counts` (the walk's counters) too.
    GuidedVertex(const WalkGuide& guide, WalkGuideStats& counts) : guide_(guide), counts_(counts) {}
    // Whether the walk's camera sample is recorded for the allocation's learning: only then do its
    // decisions explore (allocation.h).
    void set_learning(bool learning) { learning_ = learning; }

    // Begins the vertex mi (mi.medium set), reached by this object's last distance decision (whose
    // scattering leaf it keeps), or, with `known_leaf` >= 0, in that leaf (a leaf holding mi.p: tests and
    // benches that place vertices themselves). Looks nothing up.
    void init(const MediumInteraction& mi, int known_leaf = -1);
    // No vertex (the path's ray leaves from the camera or a surface). The last leaf found stays a hint.
    void clear();
    // The walk splits the path here: keeps the vertex's leaf and direction decision (built now if not
    // yet: a copy made at the distance stage scatters here too) for its copies; returns their token.
    int keep();
    // A copy resumes at mi, the vertex keep() returned `kept` for (-1: begun anew, as init).
    void resume(const MediumInteraction& mi, int kept);
    bool active() const { return active_; }
    const MediumInteraction& interaction() const { return mi_; }

    // The vertex's kd leaf (-1: outside the field), found on the first call.
    int leaf();
    // The leaf found last (-1: none): a guess for a point near the path's last vertex (a surface's).
    int hint() const { return hint_; }

    // The distance decision of `query`, whose ray leaves from this point (the vertex, or the camera
    // or a surface when not active); `camera_guided`: the camera segment's P_G from the pixel buffer
    // (NaN: not a camera segment, or none); `record` (may be null): what the decision sampled from, for
    // the recorders. The scattering vertex's leaf, where the decision knows it, is kept for init.
    FreeFlightSample sample_distance(const DistanceQuery& query, float camera_guided, Sampler& sampler,
                                     DecisionRecord* record);

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
    // Whether the direction decision was made unguided because the allocation's share is 0 (a guide
    // could have made it: the learning records it).
    bool direction_guidable() const { return direction_guidable_; }

    // The continuation's estimate for `stage` along w (guided_continuation.h) from the vertex's leaf
    // where the guide trusts it (TrustRule::trusted); 0 otherwise.
    Color3 estimate(ContinuationStage stage, const Vec3f& w);

  private:
    // The leaf a distance decision of a ray leaving from this point reads: the vertex's, or where
    // there is no vertex and `needed`, the leaf at the ray's origin (-1: none).
    int origin_leaf(const DistanceQuery& query, bool needed);
    // The direction mixture's phase probability in leaf `index`: 1 - the guided share
    // (TrustRule::guided_share); 1: the phase function alone.
    float phase_probability(int index);
    // The distance decision's inputs at its origin, the allocation's share of its cell included.
    DistanceInput distance_input(const DistanceQuery& query, float camera_guided);
    // The prepared field for `phase` (the last medium's kept: no map lookup per decision).
    const PhaseField& phase_field(const PhaseFunction& phase);
    // The phase function's prepared lobes (the guide's; the last medium's kept: no map lookup per vertex).
    const PhaseLobes& phase_lobes(const PhaseFunction& phase);

    const WalkGuide& guide_;
    WalkGuideStats& counts_;
    MediumInteraction mi_;  // a copy: the walk's vertex may move before the decisions are made
    bool active_ = false;
    int reached_ = -1;      // the scattering leaf the last distance decision found (-1: none), for init
    int handed_ = -1;       // the current vertex's: reached_ when it began
    int leaf_ = -1;         // leaf(), when found_
    bool found_ = false;
    int hint_ = -1;
    bool prepared_ = false;  // prepare_direction ran for this vertex
    bool direction_guidable_ = false;
    bool learning_ = false;
    DistanceScratch scratch_;  // the distance decisions' (kept for its storage)
    std::optional<GuidedDirectionSampler> direction_;
    // What keep() kept, per token (the camera sample's splits; its copies read them).
    struct Kept {
        int leaf = -1;
        bool found = false, prepared = false, guidable = false;
        std::optional<GuidedDirectionSampler> direction;
    };
    std::vector<Kept> kept_;
    const PhaseFunction* field_phase_ = nullptr;
    PhaseField field_;
    const PhaseFunction* lobes_phase_ = nullptr;
    const PhaseLobes* lobes_ = nullptr;
    PhaseLobes own_lobes_;
};

}  // namespace volguide
