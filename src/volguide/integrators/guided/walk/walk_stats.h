#pragma once
// The guided walk's counters (--stats): what each walk's decisions did, counted by the objects that
// make them (GuidedVertex, SurfaceVertex, GuidedWalkPolicy) into the walk's own WalkGuideStats, and the
// guided decisions' counted work (volpath/work.h) the walk takes after each decision; the walks' sums
// over all threads in a WalkStatsTally (WalkGuide keeps one per render).
#include <tbb/enumerable_thread_specific.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "volguide/integrators/volpath/work.h"

namespace volguide {

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

// The walks' counters summed over threads: each walk adds its own once, at its end (any thread).
class WalkStatsTally {
  public:
    void add(const WalkGuideStats& walk) const { per_thread_.local() += walk; }
    WalkGuideStats total() const;

  private:
    mutable tbb::enumerable_thread_specific<WalkGuideStats> per_thread_;
};

}  // namespace volguide
