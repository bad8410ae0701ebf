#include "volguide/integrators/guided/estimates/cost_model.h"

namespace volguide {

CostModel CostModel::fitted() {
    // ns per unit, in volpath/work.h's order; the output of bench/fit_cost_model.py.
    return CostModel({
        665.9,  // camera_samples
        0.0,  // intersections
        1094.0,  // shadow_rays
        0.0,  // medium_vertices
        84.7,  // surface_vertices
        0.0,  // segments
        1294.5,  // tracked_segments
        278.5,  // continuations
        4458.4,  // branches
        409.6,  // recorded_events
        200.0,  // policy_samples
        363.5,  // guided_segments
        162.0,  // bins
        246.7,  // descents
        0.0,  // lobe_pairs
        236.5,  // guide_evals
        579.1,  // surface_guides
        0.0,  // estimates
    });
}

}  // namespace volguide
