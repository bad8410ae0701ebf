// Issue 59: the allocation (integrators/guided/estimates/allocation.h) turns off what loses and keeps
// what wins, on scenes built for either: the benchmark's aniso (a dense g = 0.9 medium lit by a spot
// from the side, where product guiding wins by an order of magnitude: bench/RESULTS.md) keeps its
// direction decisions guided; the benchmark's sss (a dense, high-albedo sphere under a small light,
// where no guided decision pays at equal time) ends its coarse stage unguided and renders the rest as
// the unguided walk. Also: the allocation and the stage are the same for one and two threads.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "support/cli.h"
#include "support/test_support.h"
#include "volguide/integrators/guided/guided_volpath.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

using namespace volguide;
using namespace volguide::test;

namespace {

struct AllocatedRender {
    std::map<std::string, double> stats;
    Image image;
};

// The benchmark scene with guided_volpath's defaults (fewer photons: the test's film is small).
AllocatedRender render_bench(const std::string& scene, int spp, int threads) {
    TempDir dir("allocation-" + scene);
    const std::string integrator = dir.write(
        "integrator.xml", R"(<scene version="3.0.0"><integrator type="guided_volpath">
            <integer name="max_depth" value="$max_depth"/><integer name="photons" value="250000"/>
        </integrator></scene>)");
    LoadOptions load;
    load.defines = {{"width", "32"}, {"height", "24"}, {"integrator", "guided_volpath"}, {"integrator_xml", integrator}};
    auto loaded = load_scene(source_dir() + "/bench/scenes/" + scene + ".xml", load);
    RenderOptions options;
    options.spp = spp;
    options.seed = 7;
    options.threads = threads;
    AllocatedRender out;
    out.image = render(*loaded, options).mean;
    for (const auto& [k, v] : loaded->integrator().statistics()) out.stats[k] = v;
    return out;
}

}  // namespace

TEST(Allocation, KeepsProductGuidingWhereItWins) {
    const AllocatedRender r = render_bench("aniso", 16, 2);
    EXPECT_EQ(r.stats.at("training_stage"), 1.0);  // the full field was trained: guiding pays
    EXPECT_GT(r.stats.at("allocation_gain"), 2.0);
    EXPECT_GT(r.stats.at("allocation_direction_guided_fraction"), 0.3);
}

TEST(Allocation, StopsGuidingWhereNothingPays) {
    const AllocatedRender r = render_bench("sss", 16, 2);
    EXPECT_EQ(r.stats.at("training_stage"), 2.0);  // stopped after the coarse stage
    EXPECT_LT(r.stats.at("allocation_coarse_gain"), 1.05);
}

TEST(Allocation, SameStageAndImageForOneAndTwoThreads) {
    const AllocatedRender one = render_bench("aniso", 8, 1), two = render_bench("aniso", 8, 2);
    EXPECT_EQ(one.stats.at("allocation_gain"), two.stats.at("allocation_gain"));
    EXPECT_EQ(one.stats.at("training_stage"), two.stats.at("training_stage"));
    ASSERT_EQ(one.image.pixels.size(), two.image.pixels.size());
    for (size_t i = 0; i < one.image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(one.image.pixels[i][c], two.image.pixels[i][c]) << i;
}
