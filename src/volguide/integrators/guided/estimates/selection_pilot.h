#pragma once
// The pilot of the learned selection (learned_selection.h): a few camera samples per pixel of the guided
// walk with the configured mixtures and without guided RR/splitting, on their own random stream, each
// followed by the learner's recorder (learner.h, cell_recorder.h): one pass of the learner before the
// render. Not part of the image.
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

namespace volguide {

class Scene;
struct PreprocessContext;

struct SelectionPilotBudget {
    int spp = 2;          // camera samples per pilot pixel
    double seconds = 0.0;  // time limit (0: none)
};
inline constexpr long kPilotPixels = 256 * 256;

// The pilot's paths at most for a W x H film: spp x min(W H, kPilotPixels) (fewer blocks when the block
// grid rounds down).
uint64_t selection_pilot_paths(int W, int H, int spp);

// The pilot: `budget.spp` camera samples per pilot pixel of `walk` (the guided walk with the recorder
// as its PathRecorder), each on Sampler(seed, pixel, k, stream of the pilot), `pixel(film_uv)` the pixel
// estimate, into `learner` (its pass ended). Returns the paths traced.
uint64_t run_selection_pilot(const Scene& scene, const SelectionPilotBudget& budget,
                             const std::function<float(Point2f)>& pixel,
                             const std::function<Color3(Sampler&, const Ray&, CellRecorder&)>& walk,
                             const PreprocessContext& context, Learner& learner);

}  // namespace volguide
