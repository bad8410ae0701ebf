#pragma once
// The parameters of `guided_volpath` (docs/scene-format.md has the table), read and checked once from
// the scene's <integrator> properties. Every choice is stored once, as the enum its consumer reads (the
// walk guide's DistanceGuiding/DirectionGuiding, the roulette's RouletteMode, ...); its name in the
// scene file lives only in the choice tables of guided_volpath_settings.cpp, which both read the
// choice and print it (to_string). Settings that are not parameters (the test references: the
// tabulated distance sampler, the paper's denominator, exact estimates) are reachable from C++ only.
#include <cstdint>
#include <string>

#include "volguide/core/properties.h"
#include "volguide/guiding/field_refinement.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/roulette_splitting.h"
#include "volguide/integrators/guided/estimates/continuation_snapshot.h"
#include "volguide/integrators/guided/estimates/allocation.h"
#include "volguide/integrators/guided/estimates/pixel_estimate.h"
#include "volguide/integrators/guided/training/refinement_schedule.h"
#include "volguide/integrators/volpath/volpath.h"
#include "volguide/integrators/guided/walk/walk_guide.h"

namespace volguide {

// `estimate`: render (None), or the field's own prediction of what the camera sees through the
// media (cache_estimate.h): inscattered (compare with volpath volume_only) or incident.
enum class FieldEstimate { None, Inscattered, Incident };

struct GuidedVolPathSettings {
    VolPathSettings walk;  // max_depth, rr_depth, rr_rule, hide_emitters, equiangular, volume_only
    int64_t photons = 1000000;  // the paper uses ~50 M; 1 M trains in seconds on two cores
    // Photon collisions kept at most (0: no cap): dense media deposit tens per photon, and the
    // field's build and fit time grows with them. Fewer deposits also make fewer, larger leaves
    // (leaf_samples per leaf), so shorter distance walks (measured: bench/RESULTS.md, `max_deposits`).
    int64_t max_deposits = 2000000;
    // Focused photon emission (emission_focus.h): a pilot finds where each emitter lights a medium.
    bool photon_focus = true;
    float training_fraction = 0.25f;
    GuidingFieldSettings field;  // leaf_samples -> field.tree.max_samples, lobes -> field.lobes
    // Refinement while the image renders (field_refinement.h, refinement_schedule.h): refine_passes
    // further photon passes at most, added to the field when the schedule says; each pass deposits as
    // many collisions as all before it, at most kRefineMaxDeposits. 0: the field stays the pre-pass's.
    RefinementScheduleSettings refine;
    FieldRefinementSettings refinement;  // its `field` is a copy of `field`
    static constexpr int64_t kRefineMaxDeposits = 8000000;
    // The distance and direction decisions (guide.distance, guide.direction) and their parameters
    // (c_T, p_max, filter_A, phase_prob, ...).
    WalkGuideSettings guide;
    // The RR/splitting decision (roulette.mode) and rrs_window, rrs_q_min, rrs_q_max, rrs_max_branches.
    RouletteSplittingSettings roulette;
    // rrs=ears: its statistics' threshold and the adaptive branch budget (continuation_stats.h).
    EarsSettings ears;
    // The allocation learned while rendering (allocation.h); `allocation` false: the configured
    // mixtures and rule everywhere, nothing learned.
    bool learn_allocation = true;
    AllocationSettings allocation;
    PixelEstimateSettings pixel;      // pixel_estimate_rays, pixel_estimate_floor
    std::string save_pixel_estimate;  // EXR of I (RGB, before the floor), empty = none
    std::string save_field, load_field;  // resolved paths, empty = none
    FieldEstimate estimate = FieldEstimate::None;
    SourceLocation location;

    static GuidedVolPathSettings from(const Properties& props);
    // "name=value, ..." of the choices and main parameters, with the scene file's names.
    std::string to_string() const;
};

}  // namespace volguide
