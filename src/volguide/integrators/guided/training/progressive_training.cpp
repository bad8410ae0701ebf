#include "volguide/integrators/guided/training/progressive_training.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>

#include "volguide/core/parallel.h"
#include "volguide/integrators/camera_sample.h"
#include "volguide/integrators/guided/training/training_recorder.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensor.h"

namespace volguide {

namespace {

// The Sampler stream of training paths (the render loop's camera paths use stream 0).
constexpr uint64_t kTrainingStream = 0x7EA1F1E1Dull;

using Clock = std::chrono::steady_clock;

struct Tile {
    int x0, y0, x1, y1;
};

// Samples [first_sample, first_sample + spp) of every pixel of `tile`, each a walk of volpath with
// the recorder as its PathRecorder, their training samples appended to `out` in pixel and sample order.
void trace_tile(const Scene& scene, const VolPathIntegrator& walk, const Tile& tile, int first_sample, int spp,
                uint64_t seed, std::vector<RadianceSample>& out) {
    const Sensor& sensor = scene.sensor();
    const FilmGrid grid{sensor.film().width(), sensor.film().height(), 0};
    TrainingRecorder recorder;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x)
            for (int s = first_sample; s < first_sample + spp; ++s) {
                FilmSample sample = film_sample(grid, seed, x, y, uint64_t(s), kTrainingStream);
                const Ray ray = sensor.sample_ray(sample.film_uv, Point2f(0.5f, 0.5f)).first;
                walk.walk(scene, sample.sampler, ray, nullptr, &recorder);
                recorder.finish(out);
            }
}

// Progress of iteration (first_sample, spp) with `share` of its tiles done.
Progress training_progress(int first_sample, int spp, double share, double total_spp, double elapsed) {
    Progress p;
    p.phase = "training";
    p.fraction = (double(first_sample) + double(spp) * share) / total_spp;
    p.spp_done = first_sample;
    p.spp_target = int(total_spp);
    p.elapsed = elapsed;
    return p;
}

}  // namespace

ProgressiveTrainingResult train_progressive(const Scene& scene, const BBox3f& bounds,
                                            const ProgressiveTrainingSettings& settings,
                                            const PreprocessContext& context) {
    ProgressiveTrainingResult result;
    VolPathSettings ws = settings.walk;
    ws.equiangular = ws.volume_only = ws.forward_first_scatter = false;
    const VolPathIntegrator walk(ws);
    GuidingFieldSettings fs = settings.field;
    fs.fluence = FluenceEstimator::PerSampleMean;

    const int W = scene.sensor().film().width(), H = scene.sensor().film().height();
    const int T = std::max(settings.tile_size, 1);
    std::vector<Tile> tiles;
    for (int y = 0; y < H; y += T)
        for (int x = 0; x < W; x += T) tiles.push_back({x, y, std::min(x + T, W), std::min(y + T, H)});

    const int iterations = std::clamp(settings.iterations, 0, 30);
    const double total_spp = double((int64_t(1) << iterations) - 1);
    const auto start = Clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    const bool limited = settings.time_limit > 0;

    std::vector<RadianceSample> samples;  // all iterations so far, in (iteration, tile, pixel, sample) order
    std::mutex progress_mutex;
    for (int k = 0; k < iterations; ++k) {
        if (context.cancelled()) {
            result.cancelled = true;
            break;
        }
        // An iteration traces twice the previous one's paths: predict it from the last one.
        if (limited && k > 0 && elapsed() + 2.0 * result.iteration_seconds.back() > settings.time_limit) {
            result.time_limited = true;
            break;
        }
        const auto iteration_start = Clock::now();
        const int spp = 1 << k, first_sample = spp - 1;
        std::vector<std::vector<RadianceSample>> per_tile(tiles.size());
        std::vector<uint8_t> done(tiles.size(), 0);
        std::atomic<size_t> finished{0};
        parallel_for(size_t(0), tiles.size(), [&](size_t t) {
            if (context.cancelled()) return;
            // Iteration 0 always completes: a field needs some samples.
            if (limited && k > 0 && elapsed() > settings.time_limit) return;
            trace_tile(scene, walk, tiles[t], first_sample, spp, context.seed, per_tile[t]);
            done[t] = 1;
            const size_t n = ++finished;
            if (!context.progress) return;
            std::lock_guard lock(progress_mutex);
            context.progress(training_progress(first_sample, spp, double(n) / double(tiles.size()), total_spp,
                                               elapsed()));
        });
        bool complete = true;
        for (size_t t = 0; t < tiles.size(); ++t) {
            if (!done[t]) {
                complete = false;
                continue;
            }
            samples.insert(samples.end(), per_tile[t].begin(), per_tile[t].end());
            std::vector<RadianceSample>().swap(per_tile[t]);
        }
        if (!complete) (context.cancelled() ? result.cancelled : result.time_limited) = true;
        // Refit after every iteration: the next one will guide with it (issue 7). Even a partial
        // iteration's samples are unbiased per vertex, so they are kept.
        result.field = GuidingField::build(bounds, samples, fs);
        ++result.iterations;
        if (complete) result.spp += spp;
        result.iteration_seconds.push_back(std::chrono::duration<double>(Clock::now() - iteration_start).count());
        if (!complete) break;
    }
    result.samples = int64_t(samples.size());
    if (result.field.empty()) result.field = GuidingField::build(bounds, samples, fs);
    if (settings.keep_samples) result.sample_list = std::move(samples);
    return result;
}

}  // namespace volguide
