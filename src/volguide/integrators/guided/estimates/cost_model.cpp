#include "volguide/integrators/guided/estimates/cost_model.h"

namespace volguide {

CostModel CostModel::fitted() {
    // ns per unit, in volpath/work.h's order; the output of bench/fit_cost_model.py.
    return CostModel({
        200.0,  // camera_samples
        150.0,  // intersections
        250.0,  // shadow_rays
        100.0,  // medium_vertices
        100.0,  // surface_vertices
        55.0,   // segments
        400.0,  // tracked_segments
        20.0,   // continuations
        300.0,  // branches
        150.0,  // guided_segments
        60.0,   // bins
        40.0,   // descents
        8.0,    // lobe_pairs
        30.0,   // guide_evals
        500.0,  // surface_guides
        20.0,   // estimates
    });
}

}  // namespace volguide
