#pragma once
// The render loop: progressive passes over the image, each pass rendering a fixed number of samples
// per pixel in 16 x 16 tiles with TBB. A pass is merged into the film only when it completes, so a
// render stopped by its time budget or by cancellation is complete and unbiased at the spp of its
// last whole pass. The pass schedule depends only on the sample count, every sample draws from
// Sampler(seed, pixel, sample index) and tiles are merged in a fixed order: with a sample count the
// image is bit-identical for any number of threads.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>

#include "volguide/core/image.h"
#include "volguide/core/progress.h"
#include "volguide/core/sampler.h"
#include "volguide/integrators/integrator.h"
#include "volguide/integrators/render_state.h"
#include "volguide/render/sensor.h"
#include "volguide/render/sensors/film_buffer.h"

namespace volguide {

class Scene;

struct RenderOptions {
    int spp = 0;                   // > 0 overrides the sensor's sample_count
    // The first sample index of every pixel (`--samples FIRST:COUNT`): the render draws samples
    // [first_sample, first_sample + spp) with the same streams a render from 0 would, so chunks of
    // one render merge into it (docs/distributed.md).
    uint64_t first_sample = 0;
    double time_budget = 0;        // seconds (> 0): stop at the end of the last pass that fits
    std::optional<uint64_t> seed;  // default: the sampler's seed
    int threads = 0;               // 0 = all hardware threads
    int tile_size = 16;
    bool variance = false;         // also the per-sample variance image (always for writes_variance())
    ProgressCallback progress;
    const std::atomic<bool>* cancel = nullptr;  // set it to stop at the end of the current pass
    // Called after each pass is merged with the image so far (for convergence curves); `seconds`
    // counts from the start of the job (preprocessing included), like the time budget. Its own
    // cost is part of the render time, so keep it cheap.
    std::function<void(int spp, double seconds, const Image& mean)> on_pass;
    // Called after each pass is merged, before on_pass, with no image (render() calls the
    // integrator's Integrator::end_pass first, then this; its cost counts toward the time budget).
    std::function<void(const PassReport& pass)> end_pass;
    // Checkpoints (render_state.h): called after each merged pass (after on_pass) with `final` false,
    // and once more with `final` true when the render stops (done, cancelled or out of time) after at
    // least one pass; `state()` makes the render's state then, the integrator's included (the caller
    // decides whether to pay for it). Not after a pass whose end_pass ended with the cancel flag set
    // (the integrator's learning may have stopped short): neither then nor at the stop that follows.
    // Not for light tracers (std::invalid_argument).
    std::function<void(const std::function<RenderState()>& state, bool final)> checkpoint;
    // A checkpoint's state to go on from (not owned): the render restores its film, passes and
    // counters, and the integrator's state after preprocess(), then renders the passes that are left
    // of spp (which must be the checkpointed render's target, with its first_sample). Not for light
    // tracers (std::invalid_argument).
    const RenderState* resume = nullptr;
};

// Where a sample went wrong, to replay it (tools/replay_sample): film_sample(grid, seed, x, y,
// sample) of camera_sample.h draws it again.
struct SampleLocation {
    int x = 0, y = 0;  // film pixel (may be outside the film with sample_border)
    uint64_t sample = 0;  // the absolute sample index (FIRST + k with --samples FIRST:COUNT)
};

struct RenderStats {
    double preprocess_seconds = 0, render_seconds = 0, total_seconds = 0;
    // The process's CPU time over the passes (every thread's; the integrator's work between passes
    // included): what a cost is fitted to on a machine that is not idle (bench/fit_cost_model.py).
    double render_cpu_seconds = 0;
    uint64_t samples = 0;                           // camera samples in the image
    uint64_t discarded_samples = 0;                 // samples of an interrupted pass (not in the image)
    uint64_t nonfinite_samples = 0;                 // NaN/Inf radiance samples dropped from the image
    std::optional<SampleLocation> first_nonfinite;  // the first in pass, tile and pixel order
    int passes = 0;
    int threads = 0;
    uint64_t seed = 0;
    bool cancelled = false;     // stopped by the cancel flag
    bool time_limited = false;  // stopped by the time budget
};

struct RenderResult {
    Image mean;
    Image variance;  // per-sample variance; empty unless requested
    // Per pixel sum(w) of the filter weights (row-major), what merging parts weights them by.
    std::vector<double> weight;
    int spp = 0;     // samples per pixel in the image: indices [first_sample, first_sample + spp)
    uint64_t first_sample = 0;
    RenderStats stats;
};

// Number of samples per pixel of pass `index` (0-based): 1, 1, 2, 4, 8, 8, 8, ... so that early
// previews are quick and an interrupted pass never wastes more than the work already done.
int pass_size(int index);
// The passes of a render with `spp` samples per pixel (the last one truncated).
std::vector<int> pass_schedule(int spp);
// The tiles (T x T) covering a W x H grid and `border` pixels around it, row by row (the camera loop's and
// the light-tracing loop's).
std::vector<PixelRect> make_tiles(int W, int H, int border, int T);
// Whether a render stops before its next pass: cancelled, or past `deadline` (the first pass always
// runs); sets the reason in `stats`.
bool stopped_before_pass(const RenderOptions& options, std::chrono::steady_clock::time_point deadline, bool first,
                         RenderStats& stats);

// The integrator's pre-pass alone, as render() runs it (seed, time budget, threads, progress,
// cancellation from `options`), for saving (PreprocessContext::learn_in_prepass): what `volguide train`
// saves. Returns its seconds.
double run_preprocess(const Scene& scene, Integrator& integrator, const RenderOptions& options);

// Renders the scene's sensor with its integrator (after integrator preprocessing, which counts
// toward the time budget). The variance image is filled when the integrator writes_variance().
RenderResult render(Scene& scene, const RenderOptions& options);
// The same with another integrator than the scene's own (the Python module renders one scene with
// several integrators); `integrator` is preprocessed like the scene's.
RenderResult render(const Scene& scene, Integrator& integrator, const RenderOptions& options);

// Scene-free core, also used by tests: `radiance(film_uv, sampler)` returns one sample's value.
struct FrameSetup {
    int width = 0, height = 0;
    const ReconstructionFilter* filter = nullptr;
    bool sample_border = false;
    int default_spp = 4;  // used when options.spp == 0 and there is no time budget
    uint64_t seed = 0;    // used when options.seed is empty
    bool variance = false;
};
using RadianceFn = std::function<Color3(Point2f film_uv, Sampler& sampler)>;
RenderResult render_frame(const FrameSetup& setup, const RadianceFn& radiance, const RenderOptions& options);

}  // namespace volguide
