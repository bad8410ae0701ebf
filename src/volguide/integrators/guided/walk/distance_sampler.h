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
// the learned selection's share, and hands the scattering vertex's leaf on.
// Every member's weights use the true coefficients: unbiased whatever the field says.
#include <limits>
#include <memory>
#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/integrators/volpath/walk_policy.h"
#include "volguide/media/medium.h"

namespace volguide {

class WalkGuide;
struct WalkGuideStats;
enum class DistanceGuiding;

// What a distance decision is asked: the segment (0, tmax) of `ray` in `medium`, the path weight
// (its channel shares split the decision over the colour channels, docs/theory.md §2.6) and, for a
// camera segment, P_G from the pixel estimate's per-pixel buffer (§7.10.2; NaN: none).
struct DistanceQuery {
    const Medium& medium;
    const Ray& ray;
    float tmax;
    Color3 throughput;
    float camera_guided = std::numeric_limits<float>::quiet_NaN();
};

// What the vertex hands a decision and what the decision hands back.
struct DistanceContext {
    int origin = -1;        // in: the origin's leaf (-1: none known, or outside the field)
    float unguided = 0.5f;  // in: c_T, the unguided share of the decision's mixture
    int scattering = -1;    // out: the scattering vertex's leaf, where the decision knows it
    DecisionRecord record;  // in: its leaf (the origin's, the decision's cell); out: the mixture's parts
    std::vector<ProxySegment> proxies;  // scratch of the bins, kept between decisions for its storage
};

class DistanceSampler {
  public:
    explicit DistanceSampler(const WalkGuide& guide) : guide_(guide) {}
    virtual ~DistanceSampler() = default;
    // The decision for `query` (ctx's inputs set by the caller); counts into `counts`.
    virtual FreeFlightSample sample(const DistanceQuery& query, DistanceContext& ctx, Sampler& sampler,
                                    WalkGuideStats& counts) const = 0;

  protected:
    const WalkGuide& guide_;
};

// The member of `method`; the guide must outlive it.
std::unique_ptr<DistanceSampler> make_distance_sampler(DistanceGuiding method, const WalkGuide& guide);

}  // namespace volguide
