// Micro-benchmarks of the vmm module: lobe eval, 8-lobe mixture sample, 8 x 3 product (radiance
// VMM x phase VMM, the guided-direction setup) and a weighted EM fit of 2000 samples.
//   cmake --build build --target bench_vmm && build/bench_vmm
#include <benchmark/benchmark.h>

#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/vmm/phase_vmm.h"
#include "volguide/vmm/lobe_product.h"
#include "volguide/vmm/vmm_fast_product.h"
#include "volguide/vmm/vmm_fit.h"

using namespace volguide;

namespace {
std::vector<Vec3f> directions(int n) {
    std::vector<Vec3f> out;
    for (int i = 0; i < n; ++i) {
        Sampler s(1, 0, uint64_t(i));
        out.push_back(warp::square_to_uniform_sphere(s.next_2d()));
    }
    return out;
}

Vmm radiance_vmm(int lobes) {
    Vmm m;
    Sampler s(2, 0, 0);
    for (int k = 0; k < lobes; ++k)
        m.add_lobe(0.2f + s.next_1d(),
                   VmfLobe(warp::square_to_uniform_sphere(s.next_2d()), 1.f + 50.f * s.next_1d()));
    m.normalize_weights();
    return m;
}
}  // namespace

static void BM_VmfLobeEval(benchmark::State& state) {
    auto dirs = directions(1024);
    VmfLobe lobe(normalize(Vec3f(0.3f, 0.2f, 0.9f)), 20.f);
    size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(lobe.eval(dirs[i++ & 1023]));
    }
}
BENCHMARK(BM_VmfLobeEval);

static void BM_VmmEval8(benchmark::State& state) {
    auto dirs = directions(1024);
    Vmm m = radiance_vmm(8);
    size_t i = 0;
    for (auto _ : state) benchmark::DoNotOptimize(m.pdf(dirs[i++ & 1023]));
}
BENCHMARK(BM_VmmEval8);

static void BM_VmmSample8(benchmark::State& state) {
    Vmm m = radiance_vmm(8);
    std::vector<Point2f> u;
    for (int i = 0; i < 1024; ++i) {
        Sampler s(3, 0, uint64_t(i));
        u.push_back(s.next_2d());
    }
    size_t i = 0;
    for (auto _ : state) benchmark::DoNotOptimize(m.sample(u[i++ & 1023]));
}
BENCHMARK(BM_VmmSample8);

static void BM_VmmProduct8x3(benchmark::State& state) {
    auto dirs = directions(1024);
    Vmm m = radiance_vmm(8);
    PhaseVmm phase = hg_phase_vmm(0.7f);
    size_t i = 0;
    for (auto _ : state) {
        double z = 0.0;
        auto p = product(m, phase.oriented(dirs[i++ & 1023]), &z);
        benchmark::DoNotOptimize(p);
        benchmark::DoNotOptimize(z);
    }
}
BENCHMARK(BM_VmmProduct8x3);

// The product the guided direction sampler builds at every medium vertex (vmm/lobe_product.h):
// radiance lobes as a lobe block x an HG phase function's prepared lobes (3 lobes), vectorised.
static void BM_VmmProductFast(benchmark::State& state) {
    auto dirs = directions(1024);
    const Vmm m = radiance_vmm(int(state.range(0)));
    const PhaseLobes lobes = prepare_phase_lobes(hg_phase_vmm(0.7f));
    alignas(64) std::array<float, kLobeArrays * kVmmMaxLobes> block;
    const LobeBlock b = write_lobe_block(m, block.data());
    LobeProduct out;
    size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(out.build(b, lobes, dirs[i++ & 1023]));
        benchmark::DoNotOptimize(out);
    }
    state.counters["product_lobes"] = double(b.count * lobes.count);
}
BENCHMARK(BM_VmmProductFast)->Arg(8)->Arg(32);

static void BM_HgPhaseVmmLookup(benchmark::State& state) {
    float g = 0.1f;
    for (auto _ : state) {
        benchmark::DoNotOptimize(hg_phase_vmm(g));
        g = g > 0.98f ? 0.1f : g + 0.0137f;
    }
}
BENCHMARK(BM_HgPhaseVmmLookup);

static void BM_VmmEmFit2000(benchmark::State& state) {
    Vmm truth = radiance_vmm(4);
    std::vector<DirectionalSample> samples;
    for (int i = 0; i < 2000; ++i) {
        Sampler s(4, 0, uint64_t(i));
        Vec3f w =
            s.next_1d() < 0.5f ? warp::square_to_uniform_sphere(s.next_2d()) : truth.sample(s.next_2d());
        samples.push_back({w, truth.pdf(w) / (0.5f * InvFourPi + 0.5f * truth.pdf(w))});
    }
    VmmFitSettings settings;  // defaults: 8 lobes, MAP priors, tolerance 0.0025
    int iterations = 0;
    for (auto _ : state) {
        Vmm fit;
        iterations = fit_vmm(fit, samples, settings).iterations;
        benchmark::DoNotOptimize(fit);
    }
    state.counters["em_iterations"] = iterations;
}
BENCHMARK(BM_VmmEmFit2000)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
