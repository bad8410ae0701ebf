// Whole-render cost of the volumetric path tracer:
//  - LightShafts: `volpath` on the bundled demo (scenes/demo/light-shafts.xml: homogeneous fog,
//    sun through a window) at 160x90, reported as seconds per 1M camera paths;
//  - Cloud/majorant: `volpath` on the procedural cloud of bench_media (64^3 voxels, heterogeneous
//    medium in a null-bounded cube, sun + sky) with the tight majorant grid (1) vs every majorant
//    4x looser (4). The image mean is the same (unbiased tracking); only time changes. Null
//    collisions per real collision for the same cloud: bench_media's BM_FreeFlight.
//   cmake --build build --target bench_volpath && build/bench_volpath
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>

#include "cloud.h"
#include "render_bench.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/media/heterogeneous.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

using namespace volguide;

namespace {

void BM_LightShaftsVolpath(benchmark::State& state) {
    constexpr int kWidth = 160, kHeight = 90, kSpp = 4;
    LoadOptions load;
    load.defines = {{"width", std::to_string(kWidth)}, {"height", std::to_string(kHeight)}};
    auto scene = load_scene(std::string(VOLGUIDE_SOURCE_DIR) + "/scenes/demo/light-shafts.xml", load);
    bench::run_render_benchmark(state, *scene, kSpp, int(state.range(0)), double(kWidth) * kHeight);
}

// The cloud scene, written once to a temporary folder.
std::string cloud_scene_path() {
    static const std::string path = [] {
        namespace fs = std::filesystem;
        const fs::path dir = fs::temp_directory_path() / "volguide-bench-cloud";
        fs::create_directories(dir);
        write_vol_file((dir / "cloud.vol").string(), bench::cloud_grid(64));
        std::ofstream((dir / "cloud.xml").string()) << R"(<scene version="3.0.0">
    <integrator type="volpath"><integer name="max_depth" value="16"/></integrator>
    <medium type="heterogeneous" id="cloud">
        <volume type="gridvolume" name="sigma_t">
            <string name="filename" value="cloud.vol"/>
            <transform name="to_world"><translate value="-0.5, -0.5, -0.5"/></transform>
        </volume>
        <float name="scale" value="20"/>
        <rgb name="albedo" value="0.95"/>
        <phase type="hg"><float name="g" value="0.7"/></phase>
    </medium>
    <shape type="cube">
        <transform name="to_world"><scale value="0.5"/></transform>
        <bsdf type="null"/>
        <ref name="interior" id="cloud"/>
    </shape>
    <emitter type="directional">
        <vector name="direction" value="-1, -1, -0.5"/>
        <rgb name="irradiance" value="5"/>
    </emitter>
    <emitter type="constant"><rgb name="radiance" value="0.2, 0.3, 0.5"/></emitter>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 0.3, 2.2" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="64"/>
            <rfilter type="box"/></film>
    </sensor>
</scene>)";
        return (dir / "cloud.xml").string();
    }();
    return path;
}

void BM_CloudVolpath(benchmark::State& state) {
    constexpr int kRes = 64, kSpp = 8;
    auto scene = load_scene(cloud_scene_path());
    // The benchmark's own knob on the loaded medium (the scene owns it; nothing renders meanwhile).
    for (const auto& shape : scene->shapes())
        if (auto* m = dynamic_cast<const HeterogeneousMedium*>(shape->interior_medium()))
            const_cast<HeterogeneousMedium*>(m)->set_majorant_scale(float(state.range(0)));
    bench::run_render_benchmark(state, *scene, kSpp, 2, double(kRes) * kRes);
}

}  // namespace

BENCHMARK(BM_LightShaftsVolpath)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK(BM_CloudVolpath)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
BENCHMARK_MAIN();
