// Heterogeneous-medium tracking cost on a procedural cloud (64^3 voxels, blobs modulated by
// sinusoidal "noise", about 70 % empty): null collisions per real collision and time per
// free-flight sample (spectral tracking through the 32^3 majorant grid), tight majorants vs 4x
// loose ones; and ratio vs residual ratio tracking transmittance along one ray (var_T = the
// estimator's variance).
//   cmake --build build --target bench_media && build/bench_media
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/media/heterogeneous.h"
#include "volguide/media/phase_isotropic.h"
#include "cloud.h"

using namespace volguide;
using volguide::bench::cloud_grid;

namespace {

std::shared_ptr<HeterogeneousMedium> cloud_medium() {
    static auto m = [] {
        auto sigma = std::make_shared<Volume>(VoxelGrid(cloud_grid(64), VolumeFilter::Trilinear, VolumeWrap::Clamp),
                                              Transform::translate(Vec3f(-0.5f)));
        auto albedo = std::make_shared<Volume>(VoxelGrid(Color3(0.9f)), Transform());
        return std::make_shared<HeterogeneousMedium>(sigma, 20.f, albedo, std::make_shared<IsotropicPhase>());
    }();
    return m;
}

// Rays from a sphere of radius 1.5 towards random points of the inner half of the cloud box.
std::vector<Ray> rays(int count) {
    std::vector<Ray> out;
    for (int i = 0; i < count; ++i) {
        Sampler s(3, 0, uint64_t(i));
        const Point3f o = warp::square_to_uniform_sphere(s.next_2d()) * 1.5f;
        const Point3f target(s.next_1d() - 0.5f, s.next_1d() - 0.5f, s.next_1d() - 0.5f);
        out.emplace_back(o, normalize(target * 0.5f - o));
    }
    return out;
}

}  // namespace

static void BM_FreeFlight(benchmark::State& state) {
    auto m = cloud_medium();
    m->set_majorant_scale(float(state.range(0)));
    const auto rs = rays(4096);
    TrackingCounts counts;
    uint64_t i = 0, scattered = 0;
    for (auto _ : state) {
        Sampler s(7, 0, i);
        FreeFlightSample fs = m->sample_free_flight(rs[i % rs.size()], Infinity, Color3(1.f), s, &counts);
        scattered += fs.scattered;
        benchmark::DoNotOptimize(fs);
        ++i;
    }
    m->set_majorant_scale(1.f);
    state.counters["null_per_real"] = double(counts.null_collisions) / double(std::max<uint64_t>(counts.real_collisions, 1));
    state.counters["cells_per_sample"] = double(counts.cells) / double(i);
    state.counters["scattered_frac"] = double(scattered) / double(i);
}
BENCHMARK(BM_FreeFlight)->Arg(1)->Arg(4)->Unit(benchmark::kNanosecond);

static void BM_Transmittance(benchmark::State& state) {
    auto m = cloud_medium();
    m->set_transmittance_estimator(state.range(0) ? TransmittanceEstimator::ResidualRatio
                                                  : TransmittanceEstimator::Ratio);
    // One ray through the cloud's centre, so var_T is the estimator's variance.
    const Ray ray(Point3f(-1.5f, 0.02f, 0.01f), Vec3f(1.f, 0.f, 0.f));
    uint64_t i = 0;
    double sum = 0, sum2 = 0;
    for (auto _ : state) {
        Sampler s(9, 0, i);
        const float t = m->transmittance(ray, Infinity, s).r;
        sum += t;
        sum2 += double(t) * t;
        ++i;
    }
    m->set_transmittance_estimator(TransmittanceEstimator::ResidualRatio);
    state.counters["mean_T"] = sum / double(i);
    state.counters["var_T"] = sum2 / double(i) - (sum / double(i)) * (sum / double(i));
}
BENCHMARK(BM_Transmittance)->Arg(0)->Arg(1)->Unit(benchmark::kNanosecond);

BENCHMARK_MAIN();
