#pragma once
// PPG-style progressive training of the guiding field from camera paths (docs/theory.md §10.2).
//
// Iteration k traces 2^k samples per pixel over the film with volpath's walk and a
// TrainingRecorder (training_recorder.h), which turns every camera path's medium vertices into
// radiance samples {x_j, w_j, L^ / p} (plus the vertices' NEE samples). After each iteration the
// field is rebuilt from ALL samples collected so far: the kd-tree is rebuilt over their positions
// (leaves over `leaf_samples` split) and every leaf is refitted by batch EM, fluence =
// PerSampleMean. Why a rebuild instead of stepwise EM on persisting leaves: each sample stays an
// unbiased estimate (its weight carries its own pdf), so pooling the iterations is the
// lowest-variance use of the data, and the rebuild is a pure function of the sample list (the
// field is bit-identical for any thread count) with no decay heuristics on split leaves. Cost:
// memory of all samples so far (sizeof(RadianceSample) = 48 B per medium vertex and NEE sample;
// e.g. 31 spp x 64k pixels x ~4 vertices ~ 8 M samples ~ 380 MB), and a refit of everything after
// each iteration (~2x the final fit in total, since the sample count doubles per iteration).
// While the walk is unguided (issue 7) every iteration samples the same distribution; once the
// walk guides with the previous field, the per-sample pdfs keep the pooled estimate unbiased.
//
// Sample s of pixel i draws from Sampler(seed, i, s, kTrainingStream): a stream the final render
// never uses, so training never correlates with the image. Iteration k uses samples
// [2^k - 1, 2^(k+1) - 1), so training with n iterations uses the same paths as the first n of a
// longer training. Tiles are traced in parallel and their samples joined in tile order: the field
// is a pure function of (scene, settings, seed) for any thread count.
//
// Stopping: after `iterations` iterations; under a time limit, before an iteration predicted
// (2x the previous one, fit included) to end past it, and mid-iteration (no new tiles) once it is
// passed; on cancellation as soon as the running tiles end. Each case keeps what was traced.
#include <cstdint>
#include <vector>

#include "volguide/guiding/guiding_field.h"
#include "volguide/integrators/integrator.h"
#include "volguide/integrators/volpath/volpath.h"

namespace volguide {

class Scene;

struct ProgressiveTrainingSettings {
    VolPathSettings walk;  // max_depth, rr_depth (equiangular and the inspection modes are ignored)
    int iterations = 5;    // 1 + 2 + 4 + 8 + 16 = 31 spp
    double time_limit = 0;  // seconds (> 0) from the start of training
    GuidingFieldSettings field;  // fluence is forced to PerSampleMean
    int tile_size = 16;
    bool keep_samples = false;  // return the samples the field was built from (online learning)
};

struct ProgressiveTrainingResult {
    GuidingField field;
    int iterations = 0;     // completed (a partial last iteration counts)
    int spp = 0;            // training samples per pixel traced (of complete iterations)
    int64_t samples = 0;    // radiance samples the field was built from
    std::vector<RadianceSample> sample_list;  // those samples, with keep_samples
    std::vector<double> iteration_seconds;  // tracing + fitting, per iteration
    bool cancelled = false, time_limited = false;
};

ProgressiveTrainingResult train_progressive(const Scene& scene, const BBox3f& bounds,
                                            const ProgressiveTrainingSettings& settings,
                                            const PreprocessContext& context);

}  // namespace volguide
