#pragma once
// What guided_volpath keeps between render passes to refine its field (issue 39, refinement_schedule.h):
// the field's statistics that further photon passes add to, the schedule that decides when, the field
// before the last refinement (to undo it), where the photon stream goes on, and what the refinements
// need of preprocess()'s context. Reset by every preprocess().
#include <atomic>
#include <cstdint>
#include <memory>

#include "volguide/guiding/field_refinement.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/integrators/guided/training/refinement_schedule.h"
#include "volguide/integrators/integrator.h"

namespace volguide {

class Scene;

struct RefinementState {
    std::unique_ptr<FieldRefinement> refinement;  // refine_passes > 0: the field's statistics
    std::unique_ptr<RefinementSchedule> schedule;
    GuidingField previous_field;      // the field before the last refinement
    int64_t photon_stream_next = 0;   // the first photon index a further pass draws from
    int64_t photons_traced = 0, deposits = 0;
    double training_seconds = 0;      // the pre-pass's field: photons and fit
    RefinementReport refined;         // the refinements' splits and merges, summed
    bool undone = false;              // the last refinement was undone
    // preprocess()'s scene, seed, time budget, progress and cancel flag, for the refinements.
    const Scene* scene = nullptr;
    uint64_t seed = 0;
    double time_budget = 0;
    ProgressCallback progress;
    const std::atomic<bool>* cancel = nullptr;
};

}  // namespace volguide
