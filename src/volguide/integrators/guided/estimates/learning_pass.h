#pragma once
// A learning pass of guided_volpath's allocation outside the render (allocation.h): for a pre-pass that
// is saved and rendered by other processes (`volguide train`), the allocation is learned in the
// pre-pass instead of from the render's own passes. A few camera samples per pixel of the guided walk
// with the allocation so far, on their own random stream, each followed by the learner's recorder
// (learner.h, cell_recorder.h). Not part of the image.
//
// Its cost is bounded (issue 55): it traces at most spp x kPilotPixels paths whatever the film's size —
// on a film of more pixels, one pixel drawn in each block of a regular grid of blocks (a stratified
// subset) — and stops at a time limit when given. Without one the paths, hence the statistics, depend
// only on the seed and the film's size (deterministic for any thread count: exact sums).
#include <cstdint>
#include <functional>

#include "volguide/core/color.h"
#include "volguide/core/ray.h"
#include "volguide/core/sampler.h"
#include "volguide/integrators/guided/estimates/learner.h"
#include "volguide/integrators/integrator.h"

namespace volguide {

class Scene;
struct PreprocessContext;

struct LearningPassBudget {
    int first_sample = 0;  // the samples k of every pilot pixel: first_sample <= k < first_sample + spp
    int spp = 2;           // camera samples per pilot pixel
    double seconds = 0.0;  // time limit (0: none)
};
inline constexpr long kPilotPixels = 256 * 256;

// A pass's paths at most for a W x H film: spp x min(W H, kPilotPixels) (fewer blocks when the block
// grid rounds down).
uint64_t learning_pass_paths(int W, int H, int spp);

// The pass: `budget.spp` camera samples per pilot pixel of `walk` (the guided walk with the recorder
// as its PathRecorder), each on Sampler(seed, pixel, k, the pass's stream), `pixel(film_uv)` the pixel
// estimate, into `learner` (its pass ended). Returns the paths traced.
uint64_t run_learning_pass(const Scene& scene, const LearningPassBudget& budget,
                           const std::function<float(Point2f)>& pixel,
                           const std::function<Color3(Sampler&, const CameraRay&, CellRecorder&)>& walk,
                           const PreprocessContext& context, Learner& learner);

}  // namespace volguide
