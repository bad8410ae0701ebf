#pragma once
// The counted work of a walk: what a camera sample did, unit by unit, so that a decision's cost can be
// known without a clock (the same for any thread count and scheduling). volpath's walk
// (volpath_walk.h) counts its own units (ray queries, NEE connections, vertices, distance decisions,
// continuations, copies); a policy counts the units of its guided decisions (walk_policy.h's
// WalkPolicy::take_work) and the walk collects them after each decision. A cost model turns counts
// into time (integrators/guided/estimates/cost_model.h: per-unit weights fitted to measured CPU time,
// bench/fit_cost_model.py).
#include <array>
#include <cstddef>
#include <cstdint>

namespace volguide {

// The units, in the order the weights and the --stats names follow (kWorkNames).
enum class Work : uint8_t {
    // The walk's.
    CameraSample,   // a camera sample's walk begun (its set-up, the film's work for it)
    Intersection,   // a ray query against the scene (a segment's surface hit or escape)
    ShadowRay,      // an NEE connection: the emitter sample, its visibility and transmittance
    MediumVertex,   // a real scattering in a medium: its bookkeeping and phase sampling
    SurfaceVertex,  // a surface scattering: BSDF sampling and evaluation
    Segment,        // a distance decision asked (a ray segment in a medium)
    Tracked,        // ... of them in a medium that tracks null collisions (a heterogeneous free flight)
    Continuation,   // a continuation decision asked of the policy
    Branch,         // a copy of the path made by splitting (set up, later resumed)
    Recorded,       // an event reported to a recorder that learns from the decisions (a camera sample being learned from)
    Policy,         // a camera sample walked with a policy (its set-up and the calls every decision makes to it)
    // A guiding policy's.
    GuidedSegment,  // a guided distance decision's set-up (the field's bounds, the medium's proxy segments)
    Bin,            // a bin the guided distance decision stepped through (a leaf's estimate read; tracking: a collision)
    Descent,        // a kd-tree descent to a point's leaf
    LobePair,       // a lobe (pair) of a direction mixture built at a vertex: K x J for a product, K for a leaf's mixture
    GuideEval,      // a guided direction density evaluated or sampled (NEE's MIS, the decision itself)
    SurfaceGuide,   // a guided surface vertex's distribution (the leaf's lobes times a cosine lobe)
    Estimate,       // a field estimate read for a continuation decision
    Count
};
inline constexpr size_t kWorkUnits = size_t(Work::Count);

// The units' names in --stats ("work_" + name).
inline constexpr std::array<const char*, kWorkUnits> kWorkNames = {
    "camera_samples", "intersections", "shadow_rays",  "medium_vertices", "surface_vertices", "segments",
    "tracked_segments", "continuations", "branches", "recorded_events", "policy_samples", "guided_segments", "bins",
    "descents", "lobe_pairs", "guide_evals", "surface_guides", "estimates"};

struct WorkCounts {
    std::array<uint64_t, kWorkUnits> n{};
    uint64_t& operator[](Work w) { return n[size_t(w)]; }
    uint64_t operator[](Work w) const { return n[size_t(w)]; }
    void add(Work w, uint64_t count = 1) { n[size_t(w)] += count; }
    WorkCounts& operator+=(const WorkCounts& o) {
        for (size_t k = 0; k < kWorkUnits; ++k) n[k] += o.n[k];
        return *this;
    }
    bool empty() const {
        for (uint64_t v : n)
            if (v) return false;
        return true;
    }
};

}  // namespace volguide
