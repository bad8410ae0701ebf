#pragma once
// The parameters of `guided_volpath` (interface.md), read and checked once from the scene's
// <integrator> properties. Every choice is stored once, as the enum its consumer reads (the walk
// guide's DistanceGuiding/DirectionGuiding, the roulette's RouletteMode, ...); its name in the scene
// file lives only in the choice tables of guided_volpath_settings.cpp, which both read the choice
// and print it (to_string).
#include <cstdint>
#include <string>

#include "volguide/core/properties.h"
#include "volguide/guiding/field_refinement.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/roulette_splitting.h"
#include "volguide/guiding/selection.h"
#include "volguide/integrators/guided/estimates/continuation_stats.h"
#include "volguide/integrators/guided/estimates/pixel_estimate.h"
#include "volguide/integrators/guided/training/refinement_schedule.h"
#include "volguide/integrators/volpath/volpath.h"
#include "volguide/integrators/guided/walk/walk_guide.h"

namespace volguide {

// How the field is trained: the photon pre-pass (docs/theory.md §5.2, §10.1) or PPG-style from camera
// paths (§10.2, progressive_training.h).
enum class TrainingMethod { Photons, Progressive };
// How guided RR/splitting's pixel estimate I is made (pixel_estimate.h).
enum class PixelEstimateMethod { Raymarch, Render };
// `estimate`: render (None), or the field's own prediction of what the camera sees through the
// media (cache_estimate.h): inscattered (compare with volpath volume_only) or incident.
enum class FieldEstimate { None, Inscattered, Incident };

struct GuidedVolPathSettings {
    VolPathSettings walk;  // max_depth, rr_depth, hide_emitters, equiangular
    TrainingMethod training = TrainingMethod::Photons;
    int64_t photons = 1000000;  // the paper uses ~50 M; 1 M trains in seconds on two cores
    // Photon collisions kept at most (0: no cap): dense media deposit tens per photon, and the
    // field's build and fit time grows with them (bench/RESULTS.md: training overran its budget in
    // dense scenes before this cap). Fewer deposits also make fewer, larger leaves (leaf_samples per
    // leaf), so shorter distance walks: 2 M rendered better than 4 M at equal time, and 1 M did not
    // (measured: see bench/RESULTS.md, "all eight scenes at 60 s ... half the photon deposits").
    int64_t max_deposits = 2000000;
    // Focused photon emission (emission_focus.h): a pilot finds where each emitter lights a medium.
    bool photon_focus = true;
    int training_iterations = 5;  // progressive: iteration k traces 2^k spp (5: 31 spp in total)
    // Online learning (issue 22, progressive training only): the render's own guided paths of its
    // first online_spp samples per pixel are recorded and the field is rebuilt from them and the
    // training's after each pass (0: off, the field stays the training's).
    int online_spp = 0;
    float training_fraction = 0.25f;
    GuidingFieldSettings field;  // leaf_samples -> field.tree.max_samples, lobes -> field.lobes
    // Refinement while the image renders (issue 39, photon training only): refine_passes further
    // photon passes at most, added to the field (field_refinement.h: max_leaves, leaf_merge) when the
    // schedule says (refinement_schedule.h: refine_spp, refine_gain); each pass deposits as many
    // collisions as all before it, at most refine_max_deposits. refine_passes 0: the field stays the
    // pre-pass's.
    RefinementScheduleSettings refine;
    FieldRefinementSettings refinement;  // its `field` is a copy of `field`
    int64_t refine_max_deposits = 8000000;
    // The distance and direction decisions (guide.distance, guide.direction) and their parameters
    // (c_T, p_max, filter_A, phase_prob, ...).
    WalkGuideSettings guide;
    // The RR/splitting decision (roulette.mode) and rrs_window, rrs_q_min, rrs_q_max, rrs_max_branches.
    RouletteSplittingSettings roulette;
    // rrs=ears: its statistics' thresholds and the adaptive branch budget (continuation_stats.h).
    EarsSettings ears;
    // Learned selection (guiding/selection.h): the pilot's spp (default 2; 0: off) and the fit's parameters.
    SelectionSettings selection;
    PixelEstimateMethod pixel_estimate = PixelEstimateMethod::Raymarch;
    PixelEstimateSettings pixel;      // pixel_estimate_rays, pixel_estimate_floor
    int pixel_estimate_spp = 4;       // pixel_estimate=render
    std::string save_pixel_estimate;  // EXR of I (RGB, before the floor), empty = none
    std::string save_field, load_field;  // resolved paths, empty = none
    FieldEstimate estimate = FieldEstimate::None;
    SourceLocation location;

    static GuidedVolPathSettings from(const Properties& props);
    // "name=value, ..." of the choices and main parameters, with the scene file's names.
    std::string to_string() const;
};

}  // namespace volguide
