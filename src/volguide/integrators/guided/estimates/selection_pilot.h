#pragma once
// The pilot of the learned selection (learned_selection.h): a few camera samples per pixel of the guided
// walk with the configured mixtures and without guided RR/splitting, on their own random stream, each
// followed by the learner's recorder (learner.h, cell_recorder.h): one pass of the learner before the
// render. Not part of the image.
#include <functional>

#include "volguide/core/color.h"
#include "volguide/core/ray.h"
#include "volguide/core/sampler.h"
#include "volguide/integrators/guided/estimates/learner.h"

namespace volguide {

class Scene;
struct PreprocessContext;

// `spp` camera samples per pixel of `walk` (the guided walk with the recorder as its PathRecorder), each
// on Sampler(seed, pixel, k, stream of the pilot), `pixel(film_uv)` the pixel estimate, into `learner`
// (its pass ended). Deterministic for any thread count (exact sums).
void run_selection_pilot(const Scene& scene, int spp, const std::function<float(Point2f)>& pixel,
                         const std::function<Color3(Sampler&, const Ray&, CellRecorder&)>& walk,
                         const PreprocessContext& context, Learner& learner);

}  // namespace volguide
