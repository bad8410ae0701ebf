#pragma once
// The distance decision of `guided_volpath`, one family (docs/theory.md §7): where along a ray segment
// in one medium the next real scattering happens, or that the segment is passed (Medium::
// sample_free_flight's contract: the weight, and the scattering vertex when it scattered). Three
// members, one per DistanceGuiding value:
//  - free flight: the medium's own sampling (the unguided decision), with the random numbers the
//    walk without a guide draws;
//  - incremental: the paper's incremental product sampler over the bins of the leaves the segment
//    crosses (distance_bins.h, guiding/guided_distance.h, §7.9), or guided null-collision tracking
//    in media that track null collisions (§7.7 H2, guiding/guided_collision.h);
//  - vsp: one decision per segment (scatter in it or pass it) with the guided probability of the
//    origin's leaf, in closed form in homogeneous media, by resampling the segment's tentative
//    collisions otherwise (vsp_distance.h, §7.10).
// A member is asked by the vertex the segment leaves from (GuidedVertex::sample_distance, which also
// answers camera and surface segments), never by the walk directly: the vertex knows its leaf and
// the learned selection's share, and hands the scattering vertex's leaf on. What a member reads of the
// guide is handed to it: its settings once (DistanceSettings), and with every decision the prepared
// field for the medium's phase function (DistanceInput::field, prepared_field.h) and the guided share.
// Every member's weights use the true coefficients: unbiased whatever the field says.
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/guiding/guided_distance.h"
#include "volguide/integrators/guided/walk/prepared_field.h"
#include "volguide/integrators/guided/walk/trust.h"
#include "volguide/integrators/volpath/walk_policy.h"
#include "volguide/media/medium.h"

namespace volguide {

class Scene;

// The distance decisions, one family (user names standard, incremental, vsp): free flight; the
// incremental product sampler over the bins of the leaves a segment crosses (guided null-collision
// tracking in heterogeneous media, docs/theory.md §7.7 H2); vsp, one decision per segment from the
// origin's leaf (docs/theory.md §7.10).
enum class DistanceGuiding { Standard, Incremental, Vsp };

// The family's settings (WalkGuideSettings' values).
struct DistanceSettings {
    // The incremental sampler's; its c_T is replaced per decision by 1 - the undamped guided share.
    GuidedDistanceSettings bins;
    float max_bin_optical_depth = 20.f;
    float leaf_tau_max = 1.f;  // the bins' confidence (trust.h's leaf_confidence)
    // distance=vsp in homogeneous media: the equiangular share of the scatter distance (vsp_distance.h).
    float vsp_equiangular = 0.5f;
};

// What the vertex hands a distance decision besides the query (walk_policy.h's DistanceQuery).
struct DistanceInput {
    int origin = -1;  // the origin's leaf (-1: none known, or outside the field): the decision's cell
    // The prepared field for the medium's phase function: what the decision reads of the guide.
    PhaseField field;
    // The guided share of the decision at the origin (TrustRule::guided_share): vsp's segment
    // probability reads share, the incremental sampler's bins 1 - undamped (each bin damped by its leaf).
    GuidedShare share;
    // A camera segment's P_G from the pixel estimate's per-pixel buffer (§7.10.2; NaN: none).
    float camera_guided = std::numeric_limits<float>::quiet_NaN();
    bool camera() const { return !std::isnan(camera_guided); }
};

// What a distance decision did, for the walk's counters (WalkGuideStats), which the vertex adds in one
// place: the decisions themselves only say what happened.
struct DistanceReport {
    enum class Method : uint8_t { FreeFlight, OutsideField, Tracking, Bins, Vsp };
    Method method = Method::FreeFlight;
    uint64_t steps = 0;          // bins stepped through (tracking: tentative collisions)
    uint64_t invalid = 0;        // ... of them without a valid leaf
    uint64_t damped = 0;         // ... of them whose leaf's confidence is below 1
    uint64_t nan_fallbacks = 0;  // ... of them whose guided probability was not finite
    bool guided = false;         // the bins' decision followed the guided probabilities
    // vsp: a camera segment (the pixel buffer's P_G); made with the unguided probability (no leaf or
    // estimate); by resampling (heterogeneous); scattered inside the segment; from the equiangular share.
    bool camera = false, unguided = false, resampled = false, scattered = false, equiangular = false;
};

// What a distance decision hands back besides its sample.
struct DistanceOutcome {
    int scattering = -1;    // the scattering vertex's leaf, where the decision knows it
    DecisionRecord record;  // the mixture's parts (for the recorders), of the origin's cell
    DistanceReport report;  // what it did (the counters)
};

// The bins' scratch, kept between a walk's decisions for its storage.
struct DistanceScratch {
    std::vector<ProxySegment> proxies;
};

class DistanceSampler {
  public:
    // The scene (the lights vsp's equiangular share aims at) must outlive the member.
    DistanceSampler(const DistanceSettings& settings, const Scene& scene) : settings_(settings), scene_(scene) {}
    virtual ~DistanceSampler() = default;
    // The decision for `query` from the vertex's `in`, its outcome in `out` (out.record.leaf set by the
    // caller).
    virtual FreeFlightSample sample(const DistanceQuery& query, const DistanceInput& in, DistanceScratch& scratch,
                                    Sampler& sampler, DistanceOutcome& out) const = 0;

  protected:
    DistanceSettings settings_;
    const Scene& scene_;
};

// The member of `method`; the scene must outlive it.
std::unique_ptr<DistanceSampler> make_distance_sampler(DistanceGuiding method, const DistanceSettings& settings,
                                                       const Scene& scene);

}  // namespace volguide
