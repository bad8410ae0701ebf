#pragma once
// What every guided decision of `guided_volpath`'s walk reads (docs/theory.md §7–9): the guiding field
// and, prepared from it once per phase function, the estimates the decisions look up — the
// in-scattered cache, the per-leaf tables of L~_i and L~ (leaf_estimates.h), the leaf groups of the
// distance walk (leaf_groups.h), the phase function's VMM — with each leaf's extent (its confidence),
// the direction decisions' distribution per leaf (the indirect light), the learned selection, the
// configured distance decision (distance_sampler.h) and the counters. The decisions themselves are
// made by the vertex objects (GuidedVertex at a medium vertex, SurfaceVertex at a surface) and
// GuidedContinuation, asked by GuidedWalkPolicy (guided_walk_policy.h), which volpath's walk calls.
#include <tbb/enumerable_thread_specific.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "volguide/guiding/guided_direction.h"
#include "volguide/guiding/guided_distance.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/inscatter_cache.h"
#include "volguide/guiding/leaf_estimates.h"
#include "volguide/guiding/leaf_groups.h"
#include "volguide/integrators/guided/estimates/allocation.h"
#include "volguide/integrators/guided/walk/guided_surface_sampler.h"
#include "volguide/integrators/guided/walk/trust.h"
#include "volguide/integrators/volpath/work.h"
#include "volguide/media/medium.h"
#include "volguide/vmm/lobe_block.h"
#include "volguide/vmm/lobe_product.h"
#include "volguide/vmm/phase_vmm.h"

namespace volguide {

class DistanceSampler;
class Scene;

// The distance decisions, one family (distance_sampler.h; user names standard, incremental, vsp):
// free flight; the incremental product sampler over the bins of the leaves a segment crosses (guided
// null-collision tracking in heterogeneous media, docs/theory.md §7.7 H2); vsp, one decision per
// segment from the origin's leaf (docs/theory.md §7.10).
enum class DistanceGuiding { Standard, Incremental, Vsp };

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

// The guided decisions' counters, declared once: X(member, name, of) is a counter, the name --stats
// reports it under, and the counter it is reported as a fraction of (1: reported as a count).
// WalkGuideStats's members, their sum and named() are generated from this list.
#define VOLGUIDE_WALK_GUIDE_COUNTERS(X)                                                                    \
    /* guided distance decisions */                                                                        \
    X(distance_queries, "distance_queries", 1)                                                             \
    /* bins stepped through by them (tracking: tentative collisions) */                                    \
    X(distance_steps, "distance_average_steps", distance_queries)                                          \
    /* bin queries whose decisions followed the guided probabilities */                                    \
    X(guided_strategy, "distance_guided_fraction", distance_queries)                                       \
    /* queries by guided null-collision tracking (H2) */                                                   \
    X(guided_tracking, "distance_tracking_fraction", distance_queries)                                     \
    /* bins (tracking: collisions) stepped through without a valid leaf */                                 \
    X(invalid_bins, "distance_invalid_bin_fraction", distance_steps)                                       \
    /* bins (collisions) whose guided probability was not finite (§7.6) */                                 \
    X(nan_fallbacks, "distance_nan_fallbacks", 1)                                                          \
    /* segments that miss the field: ordinary free flight */                                               \
    X(distance_outside_field, "distance_outside_field", 1)                                                 \
    /* distance=vsp: segment decisions (homogeneous media) */                                              \
    X(vsp_queries, "distance_vsp_queries", 1)                                                              \
    /* ... that scattered inside the segment */                                                            \
    X(vsp_scattered, "distance_vsp_scattered_fraction", vsp_queries)                                       \
    /* ... made with the unguided probability (no valid leaf or estimate at the origin) */                 \
    X(vsp_unguided, "distance_vsp_unguided_fraction", vsp_queries)                                         \
    /* ... by resampling the segment's tentative collisions (heterogeneous media) */                      \
    X(vsp_resampled, "distance_vsp_resampled_fraction", vsp_queries)                                       \
    /* ... of a camera segment, with P_G from the camera-ray buffer (PixelEstimate) */                    \
    X(vsp_camera, "distance_vsp_camera_fraction", vsp_queries)                                             \
    /* ... whose scatter distance came from the equiangular mixture (a light point to aim at) */            \
    X(vsp_equiangular, "distance_vsp_equiangular_fraction", vsp_scattered)                                 \
    /* directions sampled at medium vertices */                                                            \
    X(direction_samples, "direction_samples", 1)                                                           \
    /* ... from the guiding VMM (the rest from the phase function) */                                      \
    X(direction_guided, "direction_guided_fraction", direction_samples)                                    \
    /* vertices without a valid leaf (phase only) */                                                       \
    X(direction_unguided_vertices, "direction_unguided_vertex_fraction", direction_samples)                \
    /* bins whose leaf is optically larger than leaf_tau_max */                                            \
    X(damped_bins, "distance_damped_bin_fraction", distance_steps)                                         \
    /* queries from a vertex in a leaf of confidence < kSkipConfidence (trust.h) */                                  \
    X(distance_skipped, "distance_skipped", 1)                                                             \
    /* vertices whose leaf is optically larger than leaf_tau_max */                                        \
    X(direction_damped_vertices, "direction_damped_vertex_fraction", direction_samples)                    \
    /* diffuse surface vertices offered to surface guiding */                                              \
    X(surface_vertices, "surface_vertices", 1)                                                             \
    /* ... that found a valid leaf (mixture sampling) */                                                   \
    X(surface_guided_vertices, "surface_guided_vertex_fraction", surface_vertices)                         \
    /* directions drawn from the surface guide */                                                          \
    X(surface_guided_samples, "surface_guided_sample_fraction", surface_vertices)                         \
    /* allocation: distance decisions made unguided (share 0) */                                           \
    X(distance_unselected, "allocation_distance_unguided", 1)                                              \
    /* ... direction decisions made unguided */                                                            \
    X(direction_unselected, "allocation_direction_unguided", 1)                                            \
    /* ... surface decisions made unguided */                                                              \
    X(surface_unselected, "allocation_surface_unguided", 1)                                                \
    /* medium vertices begun (GuidedVertex, guided_vertex.h; a split copy's vertex again) */                \
    X(vertices, "guided_vertices", 1)                                                                      \
    /* ... kd-tree descents they made to find their leaf (at most one per vertex) */                      \
    X(vertex_descents, "guided_vertex_descents", vertices)                                                 \
    /* ... direction mixtures they built (at most one per vertex, none where the path ended before) */    \
    X(vertex_mixtures, "guided_vertex_mixtures", vertices)                                                 \
    /* ... of which with the leaf VMM x phase product */                                                   \
    X(vertex_products, "guided_vertex_products", vertices)                                                 \
    /* ... ended by the distance-stage continuation decision (roulette) */                                \
    X(vertex_distance_kills, "guided_vertex_distance_kills", vertices)                                     \
    /* ... split copies' vertices resumed with their leaf and direction decision (nothing found again) */  \
    X(vertices_resumed, "guided_vertices_resumed", vertices)

// The counters of the walks; a walk counts into its own (GuidedWalkPolicy's) and adds it to the
// guide's once, at its end.
struct WalkGuideStats {
#define VOLGUIDE_WALK_GUIDE_MEMBER(member, name, of) uint64_t member = 0;
    VOLGUIDE_WALK_GUIDE_COUNTERS(VOLGUIDE_WALK_GUIDE_MEMBER)
#undef VOLGUIDE_WALK_GUIDE_MEMBER
    // The guided decisions' work (volpath/work.h) since the walk last took it (WalkPolicy::take_work);
    // not part of the sums (the walk reports the totals).
    WorkCounts work;
    WalkGuideStats& operator+=(const WalkGuideStats& o);
    // Named values for --stats.
    std::vector<std::pair<std::string, double>> named() const;
};

class WalkGuide {
  public:
    // The field and the scene must outlive the guide.
    WalkGuide(const Scene& scene, const GuidingField& field, const WalkGuideSettings& settings);
    ~WalkGuide();

    const WalkGuideSettings& settings() const { return settings_; }
    const Scene& scene() const { return scene_; }
    const GuidingField& field() const { return field_; }
    bool guides_distance() const { return settings_.distance != DistanceGuiding::Standard; }
    bool guides_direction() const { return settings_.direction != DirectionGuiding::Phase; }
    bool guides_surfaces() const { return settings_.surface && guides_direction(); }
    // The configured distance decision (distance_sampler.h) and free flight, which a vertex takes
    // where guiding cannot pay (a leaf of low confidence, a cell the allocation left unguided).
    const DistanceSampler& distance() const { return *distance_; }
    const DistanceSampler& free_flight() const { return *free_flight_; }

    // The leaf at x (-1 outside the field), without a descent when `hint` (a guess: a nearby
    // vertex's leaf) holds x; `descents` counts the descent made.
    int leaf_at(const Point3f& x, int hint, uint64_t& descents) const;
    // The confidence of `leaf` at extinction sigma_t (trust.h's leaf_confidence); 1 for -1.
    float confidence(int leaf, const Color3& sigma_t) const;
    // The guided share of the decision at `point` (trust.h), the one rule for how much a decision
    // follows the guide: s = s_0 x the confidence of point.leaf at point.sigma_t, s_0 the learned share
    // point.learned where one was learned, else the configured one (1 - c_T, 1 - phase_prob,
    // 1 - bsdf_prob for the distance, direction and surface decisions); s = 0 where the learned share
    // is 0 (Unselected) and at a medium vertex whose leaf's confidence is below kSkipConfidence
    // (Skipped). The distance family keeps its mixture as the unguided share c_T (GuidedDistanceSettings),
    // so its s_0 is 1 - c_T with c_T = 1 - the learned share. Every decision's mixture takes 1 - s (the
    // incremental distance decision 1 - undamped, its bins damped by their own leaves).
    GuidedShare guided_share(const TrustPoint& point) const;
    // Whether the field's estimate at `leaf` may be read at extinction sigma_t (the continuation's
    // estimate): a leaf whose confidence is at least kSkipConfidence.
    bool trusted(int leaf, const Color3& sigma_t) const {
        return leaf >= 0 && confidence(leaf, sigma_t) >= kSkipConfidence;
    }
    const std::vector<float>& leaf_extents() const { return leaf_extent_; }

    // The estimates prepared for a phase function (null: none, e.g. no guided distance decision).
    const LeafEstimates* estimates_for(const PhaseFunction& phase) const;
    const LeafGroups* groups_for(const PhaseFunction& phase) const;
    // The phase function's lobes, prepared once per phase mean cosine (null: a phase function of no
    // medium of the scene).
    const PhaseLobes* phase_lobes(const PhaseFunction& phase) const;
    // The distribution the direction decisions follow in `leaf` (a valid index), as a lobe block
    // (empty where the leaf has none): the leaf's indirect light (GuidingLeaf::vmm_indirect): NEE
    // already samples the light that comes straight from the emitters at every vertex, so the
    // continuation's zero-variance target is f_p times the rest (docs/theory.md §8.3). One copy of
    // every leaf's mixture at its own lobe count, shared by every decision.
    LobeBlock direction_lobes(int leaf) const { return direction_lobes_.block(leaf); }
    // The same mixture as the field holds it (the surface guide's product reads it), null where the
    // leaf has none.
    const Vmm* direction_vmm(int leaf) const;
    // Memory per leaf of what the decisions read (--stats): the direction decisions' lobe blocks, the
    // estimate tables (every phase function's), the kd-tree (nodes and leaf records) and the field's
    // own leaf (its mixtures at full capacity, which training fills and no decision reads).
    std::vector<std::pair<std::string, double>> memory_named() const;

    // The field's estimates at the valid leaf `leaf` (guided RR and splitting, docs/theory.md §9.3;
    // the distance decisions): L~_i(x, d) for a ray along d, and L~(x, w) arriving from w. Both
    // from the per-leaf tables when they exist.
    Color3 inscattered(int leaf, const PhaseFunction& phase, const Vec3f& d) const;
    Color3 incident(int leaf, const PhaseFunction& phase, const Vec3f& w) const;
    // The guided volume scattering probability of a segment leaving the valid leaf `leaf` along w
    // (docs/theory.md §7.10): P_G = albedo (1 - T) <L~_i(w)> / <L~(w)>, clamped to [0, 1], with
    // `unguided` = 1 - T the segment's unguided scattering probability, from the leaf's tables
    // (one lookup). NaN (the caller takes the unguided probability) for leaf < 0 or where the
    // estimates say nothing (L~ and L~_i both 0, or not finite). It shapes a probability only.
    float scatter_probability(int leaf, const PhaseFunction& phase, const Vec3f& w, float albedo,
                              float unguided) const;

    // The allocation (estimates/allocation.h): per cell, the guided share of each decision and the
    // continuation's rule; empty (the default) keeps the configured mixtures. Set between passes.
    void set_allocation(Allocation allocation) { allocation_ = std::move(allocation); }
    const Allocation& allocation() const { return allocation_; }
    // The allocation's cell of a leaf (-1: outside the field) and how many there are.
    size_t selection_cell(int leaf) const { return leaf >= 0 ? size_t(leaf) : field_.leaves().size(); }
    size_t selection_cells() const { return field_.leaves().size() + 1; }
    // The guided shares the configuration sets (what the pilot samples with): distance, direction, surface.
    std::array<float, kDecisionKinds> configured_shares() const;

    // A walk's counters, added at its end (any thread).
    void add_stats(const WalkGuideStats& walk) const { stats_.local() += walk; }
    WalkGuideStats stats() const;
    // The distance walk's leaf groups per phase mean cosine and their total (0 without merging).
    size_t leaf_group_count() const;

  private:
    const Scene& scene_;
    const GuidingField& field_;
    WalkGuideSettings settings_;
    std::map<float, InscatterCache> inscatter_;  // by phase mean cosine
    std::map<float, LeafEstimates> estimates_;   // by phase mean cosine (reads inscatter_)
    std::map<float, LeafGroups> groups_;   // by phase mean cosine (built on estimates_), if merging
    std::map<float, PhaseLobes> phase_lobes_;  // by phase mean cosine
    std::vector<float> leaf_extent_;  // cube root of each leaf's volume
    LobeStore direction_lobes_;       // per leaf: vmm_indirect where valid_indirect
    Allocation allocation_;
    std::unique_ptr<DistanceSampler> distance_, free_flight_;
    mutable tbb::enumerable_thread_specific<WalkGuideStats> stats_;
};

}  // namespace volguide
