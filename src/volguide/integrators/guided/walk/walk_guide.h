#pragma once
// What every guided decision of `guided_volpath`'s walk reads (docs/theory.md §7–9), assembled once per
// render from three parts: the prepared field (prepared_field.h: the field and the estimates, tables,
// groups and lobes prepared from it), the trust rule (trust.h: how much each decision follows it) and
// the configured distance decision (distance_sampler.h), with the allocation (estimates/allocation.h)
// and the walks' counters' sum (walk_stats.h). The decisions themselves are made by the vertex objects (GuidedVertex
// at a medium vertex, SurfaceVertex at a surface) and GuidedContinuation, asked by GuidedWalkPolicy
// (guided_walk_policy.h), which volpath's walk calls.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "volguide/guiding/guided_direction.h"
#include "volguide/guiding/guided_distance.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/integrators/guided/estimates/allocation.h"
#include "volguide/integrators/guided/walk/distance_sampler.h"
#include "volguide/integrators/guided/walk/guided_surface_sampler.h"
#include "volguide/integrators/guided/walk/prepared_field.h"
#include "volguide/integrators/guided/walk/trust.h"
#include "volguide/integrators/guided/walk/walk_stats.h"
#include "volguide/media/medium.h"

namespace volguide {

class Scene;

struct WalkGuideSettings {
    DistanceGuiding distance = DistanceGuiding::Standard;
    GuidedDistanceSettings distance_settings;
    float max_bin_optical_depth = 20.f;
    DirectionGuiding direction = DirectionGuiding::Phase;
    float phase_prob = 0.5f;  // alpha_f: probability of sampling the phase function (§8.2)
    // Per-leaf octahedral tables of L~_i and L~ for the distance decisions (leaf_estimates.h):
    // resolution per side, 0 = exact VMM evaluation per leaf crossed (a test reference, no parameter).
    int estimate_table = 16;
    // The distance walk steps groups of leaves whose tables agree within this relative tolerance
    // (guiding/leaf_groups.h) instead of single leaves: fewer bins per decision. 0: leaves.
    float distance_merge = 0.f;
    // distance=vsp in homogeneous media: the share e of the distance conditioned on scattering drawn
    // equiangularly toward a light point (vsp_distance.h, docs/theory.md §7.10.1); 0: free flight only.
    // Heterogeneous media keep the resampled decision without it. The value from the fixed-spp
    // comparison on bench/scenes/foglamp.xml (bench/RESULTS.md, issue 37); no parameter.
    float vsp_equiangular = 0.5f;
    // Guiding confidence of a leaf: min(1, leaf_tau_max / tau_leaf), tau_leaf = sigma_t (channel
    // average, at the point / of the bin's proxy) x the cube root of the leaf's volume; why and how the
    // decisions read it: trust.h. 0: off (confidence 1).
    float leaf_tau_max = 1.f;
    // Diffuse surface vertices guided by the leaf around them (guiding/surface_guide.h), whenever
    // directions are guided: the leaf's VMM (direction=incident) or its product with the cosine lobe
    // (direction=product), mixed with BSDF sampling with probability bsdf_prob. Only leaves mostly
    // filled by a medium guide surfaces (GuidingLeaf::mostly_medium; a field without measured
    // medium fractions guides none).
    bool surface = true;
    float bsdf_prob = GuidedSurfaceSampler::kDefaultBsdfProbability;
};

class WalkGuide {
  public:
    // The field and the scene must outlive the guide.
    WalkGuide(const Scene& scene, const GuidingField& field, const WalkGuideSettings& settings);
    ~WalkGuide();

    const WalkGuideSettings& settings() const { return settings_; }
    const Scene& scene() const { return scene_; }
    const GuidingField& field() const { return prepared_.field(); }
    // What the decisions read of the field (prepared_field.h) and how much they follow it (trust.h).
    const PreparedField& prepared() const { return prepared_; }
    const TrustRule& trust() const { return trust_; }
    bool guides_distance() const { return settings_.distance != DistanceGuiding::Standard; }
    bool guides_direction() const { return settings_.direction != DirectionGuiding::Phase; }
    bool guides_surfaces() const { return settings_.surface && guides_direction(); }
    // The configured distance decision (distance_sampler.h) and free flight, which a vertex takes
    // where guiding cannot pay (a leaf of low confidence, a cell the allocation left unguided).
    const DistanceSampler& distance() const { return *distance_; }
    const DistanceSampler& free_flight() const { return *free_flight_; }

    // The allocation (estimates/allocation.h): per cell, the guided share of each decision and the
    // continuation's rule; empty (the default) keeps the configured mixtures. Set between passes.
    void set_allocation(Allocation allocation) { allocation_ = std::move(allocation); }
    const Allocation& allocation() const { return allocation_; }
    // The allocation's cell of a leaf (-1: outside the field) and how many there are.
    size_t selection_cell(int leaf) const { return leaf >= 0 ? size_t(leaf) : field().leaves().size(); }
    size_t selection_cells() const { return field().leaves().size() + 1; }
    // The guided shares the configuration sets (what exploring decisions sample with): distance,
    // direction, surface.
    std::array<float, kDecisionKinds> configured_shares() const;

    // A walk's counters, added at its end (any thread).
    void add_stats(const WalkGuideStats& walk) const { stats_.add(walk); }
    WalkGuideStats stats() const { return stats_.total(); }
    // The prepared field's memory per leaf and leaf groups (--stats; prepared_field.h).
    std::vector<std::pair<std::string, double>> memory_named() const { return prepared_.memory_named(); }
    size_t leaf_group_count() const { return prepared_.leaf_group_count(); }

  private:
    const Scene& scene_;
    WalkGuideSettings settings_;
    PreparedField prepared_;
    TrustRule trust_;  // reads prepared_'s leaf extents
    Allocation allocation_;
    std::unique_ptr<DistanceSampler> distance_, free_flight_;
    WalkStatsTally stats_;
};

}  // namespace volguide
