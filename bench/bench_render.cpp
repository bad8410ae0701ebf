// Whole-render time of the demo scene (path tracer, Embree, all BSDF kinds of the demo), at a fixed
// sample count, for 1 and 2 threads. Reproduce: build/bench_render --benchmark_filter=Demo
#include <benchmark/benchmark.h>

#include "render_bench.h"
#include "volguide/scene/loader.h"

using namespace volguide;

namespace {

constexpr int kRes = 160, kSpp = 16;

void BM_DemoRender(benchmark::State& state) {
    LoadOptions load;
    load.defines = {{"res", std::to_string(kRes)}};
    auto scene = load_scene(std::string(VOLGUIDE_SOURCE_DIR) + "/scenes/demo/cornell-box.xml", load);
    bench::run_render_benchmark(state, *scene, kSpp, int(state.range(0)), double(kRes) * kRes);
}

}  // namespace

BENCHMARK(BM_DemoRender)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK_MAIN();
