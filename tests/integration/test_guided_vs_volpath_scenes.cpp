// Issues 7 and 8: guided_volpath's full system (its defaults: distance=incremental
// direction=product with surface guiding, rrs=grrs with the ray-marched pixel estimate and the
// ADRRS window s = 5) against volpath on the benchmark scenes `shafts`, `cloud`, `sss` and `fogbox`
// (bench/scenes), guided RR alone and the paper's window (s = 1) on `shafts`, and on issue 21's
// `densesphere` the full system with and without the branch budget (against volpath with the
// bounded roulette), per pixel:
// two independent renders at a small resolution, each with its own per-sample variance (--variance),
// z = (a - b) / sqrt(var_a / n_a + var_b / n_b) per pixel and channel, two-sided, Šidák-corrected at
// alpha = 0.01 over the pixel-channels; at least 99.5 % must pass (own variances are noisy estimates
// where the weights are heavy-tailed: a few pixel-channels may exceed the corrected level without a
// bias), and the image means must agree within 4 standard errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "support/bench_two_sample.h"
#include "support/cli.h"
#include "support/test_support.h"
#include "volguide/render/image_io.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// `guided_xml`: an integrator file for the guided render (empty: guided_volpath's defaults);
// `rr_rule`: volpath's roulette.
void compare_scene(const std::string& scene, int spp_volpath, int spp_guided, const std::string& guided_xml = "",
             const std::string& rr_rule = "mitsuba") {
    TempDir dir("guided-vs-volpath-" + scene);
    const BenchRender v =
        render_bench_scene(dir, scene, "volpath", spp_volpath, 11, {"-D", "integrator=volpath", "-D", "rr_rule=" + rr_rule});
    std::vector<std::string> defines = {"-D", "integrator=guided_volpath"};
    if (!guided_xml.empty()) defines.insert(defines.end(), {"-D", "integrator_xml=" + dir.write("guided.xml", guided_xml)});
    const BenchRender g = render_bench_scene(dir, scene, "guided", spp_guided, 12, defines);
    expect_same_expectation(v, g, scene, "volpath", "guided");
}

}  // namespace

TEST(GuidedVsVolpathScenes, Shafts) { compare_scene("shafts", 1024, 512); }
TEST(GuidedVsVolpathScenes, Cloud) { compare_scene("cloud", 1024, 512); }
// A Cornell box in thin fog: the walls are diffuse and guided from the fog's leaves beside them
// (surface_guiding), as are the shafts room's walls above.
TEST(GuidedVsVolpathScenes, Fogbox) { compare_scene("fogbox", 1024, 512); }
// A dense scattering sphere behind a dielectric (subsurface scattering): hundreds of guided RR and
// splitting decisions per path.
TEST(GuidedVsVolpathScenes, Sss) { compare_scene("sss", 1024, 512); }

std::string rrs_integrator(const std::string& rrs, float window) {
    return R"(<scene version="3.0.0"><integrator type="guided_volpath"><integer name="max_depth" value="$max_depth"/>)"
           R"(<string name="rrs" value=")" + rrs + R"("/><float name="rrs_window" value=")" + std::to_string(window) +
           R"("/></integrator></scene>)";
}
TEST(GuidedVsVolpathScenes, ShaftsGuidedRussianRoulette) { compare_scene("shafts", 1024, 512, rrs_integrator("grr", 1.f)); }
TEST(GuidedVsVolpathScenes, ShaftsPapersWindow) { compare_scene("shafts", 1024, 512, rrs_integrator("grrs", 1.f)); }

// Issue 37: the full system with distance="vsp" (one decision per segment) on the homogeneous fogbox
// (closed form) and the heterogeneous cloud (the segment's tentative collisions resampled).
static std::string vsp_integrator() {
    return R"(<scene version="3.0.0"><integrator type="guided_volpath"><integer name="max_depth" value="$max_depth"/>)"
           R"(<string name="distance" value="vsp"/></integrator></scene>)";
}
TEST(GuidedVsVolpathScenes, FogboxVspDistance) { compare_scene("fogbox", 1024, 512, vsp_integrator()); }
TEST(GuidedVsVolpathScenes, CloudVspDistance) { compare_scene("cloud", 1024, 512, vsp_integrator()); }

// Issue 20: the full system with the distance walk over leaf groups (distance_merge).
TEST(GuidedVsVolpathScenes, ShaftsDistanceRegions) {
    compare_scene("shafts", 1024, 512,
            R"(<scene version="3.0.0"><integrator type="guided_volpath"><integer name="max_depth" value="$max_depth"/>)"
            R"(<float name="distance_merge" value="0.3"/></integrator></scene>)");
}

// Issue 21's dense back-lit sphere (sigma_t 8, albedo 0.995, g 0.6): the full system, and with the
// branch budget of a quarter of the cap, against volpath with the bounded roulette (finite variance
// there; Mitsuba's rule is unbiased too but its per-pixel variances are heavy-tailed).
std::string budget_integrator(float budget) {
    return R"(<scene version="3.0.0"><integrator type="guided_volpath"><integer name="max_depth" value="$max_depth"/>)"
           R"(<float name="rrs_branch_budget" value=")" + std::to_string(budget) + R"("/></integrator></scene>)";
}
TEST(GuidedVsVolpathScenes, DenseSphere) { compare_scene("densesphere", 1024, 256, "", "bounded"); }
TEST(GuidedVsVolpathScenes, DenseSphereBranchBudget) {
    compare_scene("densesphere", 1024, 256, budget_integrator(16.f), "bounded");
}
