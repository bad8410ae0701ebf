#pragma once
// Shared loop of the whole-render benchmarks: renders `scene` at a fixed spp and thread count each
// iteration and reports camera paths per second, seconds per million paths and the image mean of
// the last iteration (same seed every iteration).
#include <benchmark/benchmark.h>

#include "volguide/integrators/render_loop.h"
#include "volguide/render/scene.h"

namespace volguide::bench {

inline void run_render_benchmark(benchmark::State& state, Scene& scene, int spp, int threads, double pixels) {
    RenderOptions opt;
    opt.spp = spp;
    opt.seed = 1;
    opt.threads = threads;
    double mean = 0;
    for (auto _ : state) {
        RenderResult r = render(scene, opt);
        benchmark::DoNotOptimize(r.mean.pixels.data());
        mean = 0;
        for (const Color3& p : r.mean.pixels) mean += p.average();
        mean /= double(r.mean.pixels.size());
    }
    state.counters["image_mean"] = mean;
    const double paths = pixels * spp;
    state.counters["camera_paths/s"] = benchmark::Counter(paths, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["s_per_1M_paths"] = benchmark::Counter(
        paths / 1e6, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

}  // namespace volguide::bench
