// Overhead of the render loop itself (sampler set-up, tiles, splatting, ordered merge) with a
// trivial radiance function, per filter. Reproduce: build/bench_render_loop
#include <benchmark/benchmark.h>

#include "volguide/integrators/render_loop.h"
#include "volguide/render/sensors/rfilters.h"

using namespace volguide;

namespace {

constexpr int kRes = 256, kSpp = 8;

void run(benchmark::State& state, const ReconstructionFilter& filter) {
    FrameSetup setup{kRes, kRes, &filter, false, kSpp, 1, state.range(1) != 0};
    RenderOptions opt;
    opt.threads = int(state.range(0));
    RadianceFn radiance = [](Point2f uv, Sampler& s) { return Color3(uv.x, uv.y, s.next_1d()); };
    for (auto _ : state) {
        RenderResult r = render_frame(setup, radiance, opt);
        benchmark::DoNotOptimize(r.mean.pixels.data());
    }
    state.counters["samples/s"] =
        benchmark::Counter(double(kRes) * kRes * kSpp, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_LoopBox(benchmark::State& state) {
    run(state, BoxFilter());
}
void BM_LoopGaussian(benchmark::State& state) {
    run(state, GaussianFilter());
}

}  // namespace

// Args: threads, variance (0/1).
BENCHMARK(BM_LoopBox)->Args({1, 0})->Args({2, 0})->Args({1, 1})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LoopGaussian)
    ->Args({1, 0})
    ->Args({2, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_MAIN();
