// Issue 55: guided RR and splitting bounded by its measured cost (roulette_splitting.h's adaptive budget,
// guided_continuation.h's bounded roulette) in guided_volpath's defaults:
//  - the defaults stay unbiased: the white furnace stays 1 and a point-lit fog has volpath's means;
//  - a dense, high-albedo sphere (where the old defaults made 3-8 branches per camera sample and hit the
//    cap of 64) never makes more branches than the adaptive budget, which is within the ceiling of 16:
//    the whole histogram, not a mean;
//  - the budget comes from counted work (the render's own passes, cost_model.h), so the image is the same
//    for 1 and 2 threads;
//  - a saved pre-pass's learning passes and the pixel estimate trace a bounded number of paths and rays
//    on a large film.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstring>
#include <map>
#include <string>

#include "support/furnace_grid.h"
#include "support/volpath_test_util.h"
#include "volguide/integrators/guided/estimates/pixel_estimate.h"
#include "volguide/integrators/guided/estimates/learning_pass.h"
#include "volguide/integrators/moment.h"

using namespace volguide;
using namespace volguide::test;

namespace bounded_continuation_test {

// guided_volpath's defaults but for a small training (the tests' scenes are small).
const char* kDefaults = R"(<integrator type="guided_volpath"><integer name="photons" value="100000"/>
    <integer name="max_depth" value="64"/></integrator>)";

std::string sensor_xml(const std::string& origin, int w, int h) {
    return fmt::format(R"(<sensor type="perspective"><float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="{}" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="{}"/><integer name="height" value="{}"/>
            <rfilter type="box"/></film></sensor>)",
                       origin, w, h);
}

std::string furnace_xml(const std::string& integrator) {
    return R"(<scene version="3.0.0"><integrator type="moment">)" + integrator + R"(</integrator>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <medium type="homogeneous" id="m"><rgb name="sigma_t" value="2, 1, 3"/><rgb name="albedo" value="1"/>
        <phase type="hg"><float name="g" value="0.7"/></phase></medium>
    <shape type="sphere"><bsdf type="null"/><ref name="interior" id="m"/></shape>)" +
           sensor_xml("0, 0, 4", 12, 12) + "</scene>";
}

// densesphere's medium (sigma_t 8, albedo 0.995, g 0.6) back-lit by an area light, on a floor.
std::string dense_sphere_xml(const std::string& integrator, int w = 16, int h = 12) {
    return R"(<scene version="3.0.0"><integrator type="moment">)" + integrator + R"(</integrator>
    <medium type="homogeneous" id="dense"><float name="sigma_t" value="8"/><float name="albedo" value="0.995"/>
        <phase type="hg"><float name="g" value="0.6"/></phase></medium>
    <shape type="sphere"><bsdf type="null"/><ref name="interior" id="dense"/></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="0.6"/><translate z="-2"/></transform>
        <emitter type="area"><rgb name="radiance" value="60, 55, 50"/></emitter></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="6"/><rotate x="1" angle="-90"/><translate y="-1.05"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.4"/></bsdf></shape>
    <emitter type="constant"><rgb name="radiance" value="0.02"/></emitter>)" +
           sensor_xml("0, 0.3, 5", w, h) + "</scene>";
}

struct StatsRender {
    RenderResult result;
    std::map<std::string, double> stats;
};
StatsRender render_with_stats(const std::string& xml, int spp, uint64_t seed, int threads = 0) {
    TempDir dir("bounded-continuation");
    auto scene = load_scene(dir.write("s.xml", xml));
    RenderOptions ro;
    ro.spp = spp;
    ro.seed = seed;
    ro.threads = threads;
    StatsRender out{render(*scene, ro), {}};
    const auto& moment = dynamic_cast<const MomentIntegrator&>(scene->integrator());
    for (const auto& [k, v] : moment.nested().statistics()) out.stats[k] = v;
    return out;
}

}  // namespace bounded_continuation_test

namespace bc = bounded_continuation_test;

TEST(BoundedContinuation, DefaultsKeepTheWhiteFurnaceAtOne) {
    const bc::StatsRender r = bc::render_with_stats(bc::furnace_xml(bc::kDefaults), 4096, 29);
    expect_constant_image({r.result.mean, r.result.variance, r.result.spp}, 1.0);
    EXPECT_GT(r.stats.at("rrs_decisions"), 0.0);  // guided RR/splitting decided
}

TEST(BoundedContinuation, DefaultsMatchVolpathInADenseSphere) {
    const Rendered ref = render_scene_xml(bc::dense_sphere_xml(R"(<integrator type="volpath"><integer name="max_depth"
        value="64"/></integrator>)"), 1024, 7, false);
    const bc::StatsRender g = bc::render_with_stats(bc::dense_sphere_xml(bc::kDefaults), 512, 8);
    expect_same_means({g.result.mean, g.result.variance, g.result.spp}, ref);
    // Guided RR and splitting decided (in the passes before the allocation chose for each region).
    EXPECT_GT(g.stats.at("rrs_splits"), 0.0);
    EXPECT_GT(g.stats.at("rrs_decisions"), 0.0);
}

// Every camera sample within the budget, the budget within the ceiling: the histogram's maximum, over
// 48 k camera samples of the dense sphere, and no cap hit. A free window (s = 1) that asks for many
// copies is held by the same bound, with splitting everywhere (allocation=false: the configured rule in
// every cell) and with the allocation's.
TEST(BoundedContinuation, BranchesNeverExceedTheBudgetOnADenseSphere) {
    for (const char* allocation : {"false", "true"})
        for (const char* extra : {"", R"(<float name="rrs_window" value="1"/>)"}) {
            SCOPED_TRACE(std::string(allocation) + extra);
            const std::string integrator =
                fmt::format(R"(<integrator type="guided_volpath"><integer name="photons" value="100000"/>
                <integer name="max_depth" value="64"/><boolean name="allocation" value="{}"/>{}</integrator>)",
                            allocation, extra);
            const bc::StatsRender r = bc::render_with_stats(bc::dense_sphere_xml(integrator, 24, 16), 128, 5);
            // The budget of every pass (the allocation's passes re-measure it): the largest within the ceiling,
            // and no camera sample beyond it.
            const double budget = r.stats.at("rrs_branch_budget"), largest = r.stats.at("rrs_branch_budget_max");
            EXPECT_GE(budget, 2.0);
            EXPECT_LE(largest, 16.0);
            EXPECT_LE(budget, largest);
            EXPECT_LE(r.stats.at("rrs_branches_max"), largest);
            EXPECT_EQ(r.stats.at("rrs_cap_hits"), 0.0);
            if (std::string(allocation) == "true") continue;
            EXPECT_GT(r.stats.at("rrs_splits"), 0.0);
            EXPECT_GT(r.stats.at("rrs_budget_limited"), 0.0);  // the budget, not the estimates, held it
        }
}

// Counted work, not wall-clock: the same seed and spp give the same budget and the same image for 1 and
// 2 threads.
TEST(BoundedContinuation, BudgetAndImageAreTheSameForOneAndTwoThreads) {
    const bc::StatsRender one = bc::render_with_stats(bc::dense_sphere_xml(bc::kDefaults), 8, 11, 1);
    const bc::StatsRender two = bc::render_with_stats(bc::dense_sphere_xml(bc::kDefaults), 8, 11, 2);
    EXPECT_EQ(one.stats.at("rrs_branch_budget"), two.stats.at("rrs_branch_budget"));
    EXPECT_EQ(one.stats.at("rrs_extra_branches"), two.stats.at("rrs_extra_branches"));
    ASSERT_EQ(one.result.mean.pixels.size(), two.result.mean.pixels.size());
    EXPECT_EQ(std::memcmp(one.result.mean.pixels.data(), two.result.mean.pixels.data(),
                          one.result.mean.pixels.size() * sizeof(one.result.mean.pixels[0])),
              0);
}

// A learning pass traces at most 2 x 256^2 paths and the pixel estimate marches at most 4 x 256^2 rays
// whatever the film's size (here 400 x 300 = 120 000 pixels); a small film keeps every pixel.
TEST(BoundedContinuation, LearningPassAndPixelEstimateCostsAreBounded) {
    EXPECT_EQ(learning_pass_paths(160, 120, 2), uint64_t(2 * 160 * 120));
    EXPECT_LE(learning_pass_paths(1024, 1024, 2), uint64_t(2 * kPilotPixels));
    EXPECT_GE(learning_pass_paths(1024, 1024, 2), uint64_t(2 * kPilotPixels * 9 / 10));
    EXPECT_LE(learning_pass_paths(4000, 3000, 2), uint64_t(2 * kPilotPixels));
    const EstimateGrid small = estimate_grid(160, 120, 256 * 256), large = estimate_grid(1024, 1024, 256 * 256);
    EXPECT_EQ(small.width, 160);
    EXPECT_EQ(small.height, 120);
    EXPECT_EQ(large.width, 256);
    EXPECT_EQ(large.height, 256);
    const bc::StatsRender r = bc::render_with_stats(bc::dense_sphere_xml(bc::kDefaults, 400, 300), 1, 3);
    EXPECT_LE(r.stats.at("pixel_estimate_rays"), double(4 * 256 * 256));
    EXPECT_GT(r.stats.at("pixel_estimate_rays"), double(4 * 256 * 256 * 9 / 10));
}
