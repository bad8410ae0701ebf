#include "volguide/integrators/guided/estimates/cost_model.h"

namespace volguide {

CostModel CostModel::fitted() {
    // ns per unit, in volpath/work.h's order; the output of bench/fit_cost_model.py.
    return CostModel({
        502.2,  // camera_samples
        0.0,  // intersections
        200.7,  // shadow_rays
        588.0,  // medium_vertices
        302.0,  // surface_vertices
        0.0,  // segments
        534.4,  // tracked_segments
        137.2,  // continuations
        472.3,  // branches
        316.8,  // recorded_events
        0.0,  // policy_samples
        312.9,  // guided_segments
        72.5,  // bins
        161.6,  // descents
        2.2,  // lobe_pairs
        0.0,  // guide_evals
        379.0,  // surface_guides
        71.6,  // estimates
    });
}

}  // namespace volguide
