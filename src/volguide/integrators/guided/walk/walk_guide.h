#pragma once
// The guided decisions of `guided_volpath`'s walk (docs/theory.md §7–8), between the guiding field and
// volpath's walk, which calls them through GuidedWalkPolicy (guided_walk_policy.h, a WalkPolicy) in
// place of free-flight, phase and BSDF sampling.
//
// Distance (§7.9): along a ray segment (0, tmax) in one medium, bins are the kd-tree leaves the ray
// crosses, cut at the medium's proxy segments (majorant cells of a heterogeneous medium) and split so
// that no bin is optically thicker than `max_bin_optical_depth` (§7.6). Each bin reads L~_i and L~
// of its leaf looking along the ray (channel averages, §7.8) and the proxy coefficients; the
// incremental or tabulated sampler (guiding/guided_distance.h) picks a scattering distance or the
// segment's end. The weight uses the true coefficients: exact transmittance in homogeneous media,
// the medium's unbiased estimate (residual ratio tracking) otherwise, and sigma_s at the vertex.
// Where the segment leaves the field's bounds (e.g. an infinite medium), the part beyond is
// sampled by the medium's own free flight from the exit point: two unbiased decisions in a row.
//
// Heterogeneous media with distance=incremental use guided null-collision tracking instead
// (docs/theory.md §7.7 H2; guiding/guided_collision.h): the medium's majorant walk with the guided
// scatter probability at every tentative collision, weights from the true coefficients only
// (no proxy, no separate transmittance estimate). `guided_tracking = false` keeps the bins (H1).
//
// Statistics are counted per thread and summed on request.
#include <tbb/enumerable_thread_specific.h>

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "volguide/guiding/leaf_groups.h"
#include "volguide/guiding/guided_direction.h"
#include "volguide/guiding/guided_distance.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/inscatter_cache.h"
#include "volguide/guiding/leaf_estimates.h"
#include "volguide/guiding/selection.h"
#include "volguide/integrators/guided/walk/guided_surface_sampler.h"
#include "volguide/integrators/guided/walk/vsp_distance.h"
#include "volguide/integrators/volpath/walk_policy.h"
#include "volguide/media/medium.h"

namespace volguide {

class GuidedVertex;
class Scene;

// Vsp: one decision per segment from the vertex's leaf (vsp_distance.h, docs/theory.md §7.10): in
// closed form in homogeneous media, by resampling the segment's tentative collisions otherwise.
// VspProduct: the same decision, with the distance inside the segment resampled by the field's
// in-scattered radiance at each candidate (docs/theory.md §7.11; one point lookup per candidate).
enum class DistanceGuiding { Standard, Incremental, Tabulated, Vsp, VspProduct };

struct WalkGuideSettings {
    DistanceGuiding distance = DistanceGuiding::Standard;
    GuidedDistanceSettings distance_settings;
    float max_bin_optical_depth = 20.f;
    // distance=vsp_product in homogeneous media: the candidate distances resampled per scattering
    // segment (heterogeneous media resample the majorant walk's tentative collisions instead).
    int product_candidates = 4;
    bool guided_tracking = true;  // heterogeneous media, incremental: H2 tracking (false: H1 bins)
    DirectionGuiding direction = DirectionGuiding::Phase;
    float phase_prob = 0.5f;  // alpha_f: probability of sampling the phase function (§8.2)
    // Per-leaf octahedral tables of L~_i and L~ for the distance decisions (leaf_estimates.h):
    // resolution per side, 0 = exact VMM evaluation per leaf crossed.
    int estimate_table = 16;
    // The distance walk steps groups of leaves whose tables agree within this relative tolerance
    // (guiding/leaf_groups.h) instead of single leaves: fewer bins per decision. 0: leaves.
    // Needs the tables (estimate_table > 0).
    float distance_merge = 0.f;
    // distance=vsp in homogeneous media: the share e of the distance conditioned on scattering drawn
    // equiangularly toward a light point (vsp_distance.h, docs/theory.md §7.10.1); 0: free flight only.
    // Heterogeneous media keep the resampled decision without it (guided_volpath warns). Default from
    // the fixed-spp comparison on bench/scenes/foglamp.xml (bench/RESULTS.md, issue 37).
    float vsp_equiangular = 0.5f;
    // distance=vsp: camera segments take P_G from the raymarched pixel estimate's camera-ray buffer
    // (PixelEstimate::camera_scatter_probability, docs/theory.md §7.10.2) instead of the camera's leaf.
    // guided_volpath makes the raymarch for it (pixel_estimate=render and a given pre-pass have none:
    // the leaf's lookup, as with false).
    bool vsp_camera_buffer = true;
    // Guiding confidence of a leaf: min(1, leaf_tau_max / tau_leaf), tau_leaf = sigma_t (channel
    // average, at the vertex / of the bin's proxy) x the cube root of the leaf's volume. A leaf many
    // mean free paths across holds one estimate for radiance that varies on the scale of a free path
    // (deep in a dense medium it is near-isotropic while the leaf's VMM carries the light at its
    // boundary); following it at every one of hundreds of events compounds its error into the path
    // weights. The guided distance probability and the direction mixture's guided share are scaled
    // by the confidence toward free flight and the phase function. 0: off (confidence 1).
    float leaf_tau_max = 1.f;
    // Direction guiding from the leaves' indirect distribution (GuidingLeaf::vmm_indirect): NEE
    // already samples the light that comes straight from the emitters at every medium vertex, so
    // the continuation's zero-variance target is f_p times the rest (docs/theory.md §8.3). false: the
    // full incident distribution (the paper's).
    bool direction_indirect = true;
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
    /* ... made with the product target (distance=vsp_product, or a cell that chose it) */                \
    X(vsp_product, "distance_vsp_product_fraction", vsp_queries)                                           \
    /* directions sampled at medium vertices */                                                            \
    X(direction_samples, "direction_samples", 1)                                                           \
    /* ... from the guiding VMM (the rest from the phase function) */                                      \
    X(direction_guided, "direction_guided_fraction", direction_samples)                                    \
    /* vertices without a valid leaf (phase only) */                                                       \
    X(direction_unguided_vertices, "direction_unguided_vertex_fraction", direction_samples)                \
    /* bins whose leaf is optically larger than leaf_tau_max */                                            \
    X(damped_bins, "distance_damped_bin_fraction", distance_steps)                                         \
    /* queries from a vertex in a leaf of confidence < kSkipConfidence */                                  \
    X(distance_skipped, "distance_skipped", 1)                                                             \
    /* vertices whose leaf is optically larger than leaf_tau_max */                                        \
    X(direction_damped_vertices, "direction_damped_vertex_fraction", direction_samples)                    \
    /* diffuse surface vertices offered to surface guiding */                                              \
    X(surface_vertices, "surface_vertices", 1)                                                             \
    /* ... that found a valid leaf (mixture sampling) */                                                   \
    X(surface_guided_vertices, "surface_guided_vertex_fraction", surface_vertices)                         \
    /* directions drawn from the surface guide */                                                          \
    X(surface_guided_samples, "surface_guided_sample_fraction", surface_vertices)                          \
    /* learned selection (guiding/selection.h): distance decisions made unguided (share 0) */              \
    X(distance_unselected, "selection_distance_unguided", 1)                                               \
    /* ... direction decisions made unguided */                                                            \
    X(direction_unselected, "selection_direction_unguided", 1)                                             \
    /* ... surface decisions made unguided */                                                              \
    X(surface_unselected, "selection_surface_unguided", 1)                                                 \
    /* ... continuation points where guided RR/splitting was switched off */                               \
    X(rrs_unselected, "selection_rrs_off", 1)                                                              \
    /* medium vertices begun (GuidedVertex, guided_vertex.h; a split copy's vertex again) */                \
    X(vertices, "guided_vertices", 1)                                                                      \
    /* ... kd-tree descents they made to find their leaf (at most one per vertex) */                      \
    X(vertex_descents, "guided_vertex_descents", vertices)                                                 \
    /* ... direction mixtures they built (at most one per vertex, none where the path ended before) */    \
    X(vertex_mixtures, "guided_vertex_mixtures", vertices)                                                 \
    /* ... of which with the leaf VMM x phase product */                                                   \
    X(vertex_products, "guided_vertex_products", vertices)                                                 \
    /* ... ended by the distance-stage continuation decision (roulette) */                                \
    X(vertex_distance_kills, "guided_vertex_distance_kills", vertices)

struct WalkGuideStats {
#define VOLGUIDE_WALK_GUIDE_MEMBER(member, name, of) uint64_t member = 0;
    VOLGUIDE_WALK_GUIDE_COUNTERS(VOLGUIDE_WALK_GUIDE_MEMBER)
#undef VOLGUIDE_WALK_GUIDE_MEMBER
    WalkGuideStats& operator+=(const WalkGuideStats& o);
    // Named values for --stats.
    std::vector<std::pair<std::string, double>> named() const;
};

// Scratch of the distance decisions, reused across them (no allocation per decision); owned by the
// caller (one per walk), it carries nothing from one decision to the next.
struct DistanceScratch {
    std::vector<ProxySegment> proxies;
    std::vector<DistanceBin> bins;  // tabulated only
    // For the selection pilot (selection_pilot.h). In: find the origin's leaf also where no
    // decision before found it. Out: whether the last decision drew from a guided mixture whose
    // parts are known, the leaf it was made from (-1: outside the field), the mixture's density
    // at the sample and its unguided and guided parts.
    bool record = false;
    // In: distance=vsp's guided probability P_G for this decision from the camera-ray buffer
    // (PixelEstimate::camera_scatter_probability, docs/theory.md §7.10.2) in place of the origin leaf's
    // lookup; NaN: none (the leaf's).
    float camera_guided = std::numeric_limits<float>::quiet_NaN();
    // `lookups`: the field lookups (tree descents and estimate reads) the decision made beyond
    // free flight's: the learned selection's counted cost of a distance method (selection.h).
    struct Decision {
        bool mixture = false;
        int leaf = -1;
        float pdf = 0.f, p_u = 0.f, p_g = 0.f;
        uint32_t lookups = 0;
    } decision;
};

// The decisions at a medium vertex read its kd leaf from the vertex's object (GuidedVertex,
// guided_vertex.h), found once per vertex; the distance decision hands the scattering vertex's leaf
// on (VertexLeaf) when it knows it, so that the vertex need not descend the tree again (leaf_at
// showed in aniso's profile, bench/RESULTS.md (issue 35)). A leaf handed on is trusted only where
// SpatialTree::leaf_at would provably return it (holds_point).
class WalkGuide {
  public:
    // The field and the scene must outlive the guide.
    WalkGuide(const Scene& scene, const GuidingField& field, const WalkGuideSettings& settings);

    const WalkGuideSettings& settings() const { return settings_; }
    bool guides_distance() const { return settings_.distance != DistanceGuiding::Standard; }
    bool guides_direction() const { return settings_.direction != DirectionGuiding::Phase; }
    bool guides_surfaces() const { return settings_.surface && guides_direction(); }

    // Medium::sample_free_flight's contract (weight, mi when scattered) with guided probabilities,
    // from the medium vertex `origin` at ray.o (its leaf and P_G are its answers; null: the ray
    // leaves from no medium vertex, the field is asked at ray.o); `scattering` (out): the scattering
    // vertex's leaf when the decision knows it (-1: not known).
    FreeFlightSample sample_distance(const Medium& medium, const Ray& ray, float tmax, const Color3& throughput,
                                     Sampler& sampler, GuidedVertex* origin, VertexLeaf& scattering,
                                     DistanceScratch& scratch) const;

    // Learned selection (guiding/selection.h): per selection cell, the guided share of each decision and
    // whether guided RR/splitting acts; empty (the default) keeps the configured mixtures.
    void set_selection(LearnedSelection selection) { selection_ = std::move(selection); }
    const LearnedSelection& selection() const { return selection_; }
    // The selection cell of a leaf (-1: outside the field) and how many there are.
    size_t selection_cell(int leaf) const { return leaf >= 0 ? size_t(leaf) : field_.leaves().size(); }
    size_t selection_cells() const { return field_.leaves().size() + 1; }
    // Counts a continuation point where the learned selection switched guided RR/splitting off
    // (guided_continuation.h decides).
    void count_rrs_unselected() const;
    // The guided shares the configuration sets (what the pilot samples with): distance, direction, surface.
    std::array<float, kSelectionDecisions> configured_shares() const;

    // Builds the direction sampler of the medium vertex mi in its kd leaf `leaf` (-1: none) in `out`
    // (in place: it holds a ~3 KB product mixture); phase only where the field has no valid leaf.
    void direction_sampler(const MediumInteraction& mi, const PhaseFunction& phase, int leaf,
                           std::optional<GuidedDirectionSampler>& out) const;
    // Counts one sampled direction (guided: drawn from the guiding part of the mixture).
    void count_direction(bool guided) const;

    // The direction sampler of a surface vertex: BSDF sampling mixed with the guide of the leaf
    // beside the surface on the side the path arrives from (`medium`: the medium it travelled in,
    // null for none; its extinction sets the leaf's confidence as in the medium). `guide_storage`
    // holds the product guide and must outlive `out`. Leaves `out` a pure BSDF sampler where
    // there is nothing to guide with (not diffuse, no valid leaf, surfaces not guided).
    // Returns the leaf beside the surface (-1: none), the learned selection's cell.
    int surface_sampler(const SurfaceInteraction& si, const BSDF& bsdf, const Medium* medium, Vmm& guide_storage,
                        std::optional<GuidedSurfaceSampler>& out) const;
    void count_surface_direction(bool guided) const;

    // The field's estimates at the valid leaf `leaf` for guided RR and splitting (docs/theory.md §9.3;
    // guided_continuation.h decides with them): L~_i(x, d) for a ray along d, and L~(x, w) arriving
    // from w. Both from the distance decisions' per-leaf tables when they exist.
    Color3 leaf_inscattered(int leaf, const PhaseFunction& phase, const Vec3f& d) const;
    Color3 leaf_incident(int leaf, const PhaseFunction& phase, const Vec3f& w) const;
    // The guided volume scattering probability of a segment leaving the valid leaf `leaf` along w
    // (docs/theory.md §7.10): P_G = albedo (1 - T) <L~_i(w)> / <L~(w)>, clamped to [0, 1], with
    // `unguided` = 1 - T the segment's unguided scattering probability, from the leaf's tables
    // (one lookup). NaN (the caller takes the unguided probability) for leaf < 0 or where the
    // estimates say nothing (L~ and L~_i both 0, or not finite). It shapes a probability only.
    float guided_scatter_probability(int leaf, const PhaseFunction& phase, const Vec3f& w, float albedo,
                                     float unguided) const;
    // `leaf` (a vertex's, -1: none) if its confidence at extinction sigma_t is at least
    // kSkipConfidence, else -1.
    int trusted_leaf(int leaf, const Color3& sigma_t) const;
    // The leaf at x (-1 outside the field), without a descent when `vertex_leaf` (a guess: x's, or a
    // nearby vertex's) holds it.
    int leaf_of(const Point3f& x, const VertexLeaf& vertex_leaf) const;
    // leaf_of for a medium vertex (GuidedVertex), counting the descent it makes (guided_vertex_descents).
    int vertex_leaf_of(const Point3f& x, int hint) const;
    // GuidedVertex's counters: a vertex begun, a direction mixture built (with a product or not).
    void count_vertex() const;
    void count_vertex_mixture(bool product) const;
    // A vertex the distance-stage continuation ended (GuidedWalkPolicy).
    void count_vertex_distance_kill() const;

    WalkGuideStats stats() const;
    // The distance walk's leaf groups per phase mean cosine and their total (0 without merging).
    size_t leaf_group_count() const;

  private:
    const LeafEstimates* estimates_for(const PhaseFunction& phase) const;
    const LeafGroups* groups_for(const PhaseFunction& phase) const;
    // sample_distance's decision on the bins of (0, t_end) (distance_bins.h; t_end: where the ray
    // leaves the field or reaches tmax), weighted by binned_flight.
    // The guided decision of `method` (not Standard) from the origin's leaf `origin` (-1: not known).
    // `from`: the origin's vertex object (null: none), which answers P_G.
    FreeFlightSample guided_distance(DistanceGuiding method, const Medium& medium, const Ray& ray, float tmax,
                                     int origin, GuidedVertex* from, float c_T, const Color3& throughput,
                                     Sampler& sampler, VertexLeaf& vertex_leaf, DistanceScratch& scratch) const;
    FreeFlightSample binned_distance(DistanceGuiding method, const Medium& medium, const Ray& ray, float tmax, float t_end,
                                     const LeafEstimates* estimates, float c_T, const Color3& throughput,
                                     Sampler& sampler, VertexLeaf& vertex_leaf, DistanceScratch& scratch) const;
    // distance=vsp's decision over (0, tmax) in a homogeneous medium from the origin's leaf `origin`
    // (-1: none; then free flight) and vertex object `from` (null: none), c_T the unguided share;
    // `product`: distance=vsp_product's resampled distance inside the segment.
    FreeFlightSample vsp_distance(const Medium& medium, const Ray& ray, float tmax, int origin, GuidedVertex* from,
                                  float c_T, bool product, const Color3& throughput, Sampler& sampler,
                                  VertexLeaf& vertex_leaf, DistanceScratch& scratch) const;
    // The same in any medium by resampling the segment's tentative collisions (resampled_segment_flight).
    FreeFlightSample vsp_resampled(const Medium& medium, const Ray& ray, float tmax, int origin, GuidedVertex* from,
                                   float c_T, bool product, const Color3& throughput, Sampler& sampler,
                                   VertexLeaf& vertex_leaf, DistanceScratch& scratch) const;
    // P_G of the segment along ray.d: the origin vertex's answer (GuidedVertex::scatter_probability)
    // when there is one, else from the leaf `origin`.
    float origin_scatter_probability(GuidedVertex* from, int origin, const PhaseFunction& phase, const Ray& ray,
                                     float albedo, float unguided) const;
    // The defensive unguided share c of distance=vsp's mixture from `origin` (§7.10): with the
    // camera-ray buffer's P_G (camera = true) the leaf's confidence does not apply.
    float vsp_unguided_share(int origin, const Color3& sigma_t, float c_T, bool camera) const;
    // distance=vsp_product's distance inside a homogeneous segment (HomogeneousVsp::sample_resampled)
    // with the target inscattered_along + product_floor; counts the field lookups in `lookups`.
    HomogeneousVsp::Sample vsp_product_sample(const HomogeneousVsp& vsp, float P, const Medium& medium, const Ray& ray,
                                              int origin, const Color3& sigma_t, Sampler& sampler,
                                              uint32_t& lookups) const;
    // distance=vsp_product's resampling target h(t) = inscattered_along(t) + product_floor (§7.11), one
    // object per segment: the floor read once, the candidates' leaf hint carried from one to the next,
    // the field lookups counted in `lookups`.
    class ProductTarget {
      public:
        ProductTarget(const WalkGuide& guide, const PhaseFunction& phase, const Ray& ray, int origin,
                      const Color3& sigma_t, uint32_t& lookups);
        float operator()(float t);

      private:
        const WalkGuide& guide_;
        const PhaseFunction& phase_;
        const Ray& ray_;
        Color3 sigma_t_;
        uint32_t& lookups_;
        int hint_;
        float floor_;
    };
    // distance=vsp_product's target factor at ray(t): the field's in-scattered radiance along ray.d
    // (channel average; 0 outside the field) times the leaf's confidence at extinction sigma_t, from
    // the leaf `hint` when it holds the point, else after a descent (hint becomes that leaf); counts
    // the descents and reads in `lookups`.
    float inscattered_along(const PhaseFunction& phase, const Ray& ray, float t, const Color3& sigma_t, int& hint,
                            uint32_t& lookups) const;
    // The positive floor added to that target: kProductFloor x the origin leaf's L~_i (else L~), 1
    // where the origin has neither.
    float product_floor(int origin, const PhaseFunction& phase, const Vec3f& d) const;
    // The weights of the bins' decision `ds` (the caller contract of guided_distance.h), and beyond
    // the field (t_end < tmax) the medium's own free flight.
    FreeFlightSample binned_flight(const Medium& medium, const Ray& ray, float tmax, float t_end,
                                   const DistanceSample& ds, const Color3& throughput, Sampler& sampler) const;
    // The confidence of `leaf` (distance_bins.h's leaf_confidence at its extent); 1 outside the field.
    float leaf_confidence(int leaf, const Color3& sigma_t) const;
    // Below this confidence a vertex neither builds the direction product nor walks the guided
    // bins from it: phase sampling and free flight (the guided share would be under a quarter).
    static constexpr float kSkipConfidence = 0.25f;
    // distance=vsp's least unguided share: P stays above a tenth of free flight's where the field
    // says nothing scatters (a leaf's estimate is one value for a whole segment).
    static constexpr float kVspMinUnguided = 0.1f;
    // distance=vsp_product's floor, relative to the origin's estimate (product_floor).
    static constexpr float kProductFloor = 0.1f;

    const Scene& scene_;
    const GuidingField& field_;
    WalkGuideSettings settings_;
    std::map<float, InscatterCache> inscatter_;  // by phase mean cosine
    std::map<float, LeafEstimates> estimates_;   // by phase mean cosine (reads inscatter_)
    std::map<float, LeafGroups> groups_;   // by phase mean cosine (built on estimates_), if merging
    std::map<float, PhaseVmm> phase_vmms_;
    std::vector<float> leaf_extent_;  // cube root of each leaf's volume
    // With direction_indirect: per leaf, vmm/valid replaced by vmm_indirect/valid_indirect (the
    // direction sampler reads a GuidingLeaf).
    std::vector<GuidingLeaf> direction_leaves_;
    LearnedSelection selection_;
    mutable tbb::enumerable_thread_specific<WalkGuideStats> stats_;
};

}  // namespace volguide
