// Emitter throughput (single thread): envmap sample_direction / pdf_direction / eval on a
// generated 1024x512 sky, and the constant emitter for comparison.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "volguide/core/properties.h"
#include "volguide/core/sampler.h"
#include "volguide/render/emitter.h"
#include "volguide/render/image_io.h"
#include "volguide/scene/factories.h"

using namespace volguide;

namespace {

std::shared_ptr<Emitter> make_sky() {
    Image image(1024, 512);
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const float sun = std::exp(-0.002f * float((x - 300) * (x - 300) + (y - 120) * (y - 120)));
            image.at(x, y) = Color3(0.3f + 50.f * sun, 0.4f + 40.f * sun, y < 256 ? 0.8f : 0.1f);
        }
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("volguide_bench_sky_" + std::to_string(::getpid()) + ".exr"))
                                 .string();
    write_exr(path, image);
    Properties props("emitter", "envmap", SourceLocation{"bench", 0});
    props.set("filename", "string", path, SourceLocation{"bench", 0});
    auto e = std::dynamic_pointer_cast<Emitter>(create_emitter(props));
    std::filesystem::remove(path);
    e->set_scene_bounds(BBox3f({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
    return e;
}

const Emitter& sky() {
    static std::shared_ptr<Emitter> e = make_sky();
    return *e;
}

Interaction origin() {
    Interaction it;
    it.p = Point3f(0.f);
    it.t = 0.f;
    return it;
}

void BM_EnvmapSampleDirection(benchmark::State& state) {
    const Emitter& e = sky();
    const Interaction ref = origin();
    Sampler s(1, 0, 0);
    for (auto _ : state) benchmark::DoNotOptimize(e.sample_direction(ref, s.next_2d()));
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_EnvmapSampleDirection);

void BM_EnvmapPdfDirection(benchmark::State& state) {
    const Emitter& e = sky();
    const Interaction ref = origin();
    Sampler s(2, 0, 0);
    DirectionSample ds;
    for (auto _ : state) {
        ds.d = normalize(Vec3f(s.next_1d() - 0.5f, s.next_1d() - 0.5f, s.next_1d() - 0.5f));
        benchmark::DoNotOptimize(e.pdf_direction(ref, ds));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_EnvmapPdfDirection);

void BM_EnvmapEval(benchmark::State& state) {
    const Emitter& e = sky();
    Sampler s(3, 0, 0);
    SurfaceInteraction si;
    for (auto _ : state) {
        si.wi = normalize(Vec3f(s.next_1d() - 0.5f, s.next_1d() - 0.5f, s.next_1d() - 0.5f));
        benchmark::DoNotOptimize(e.eval(si));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_EnvmapEval);

}  // namespace

BENCHMARK_MAIN();
