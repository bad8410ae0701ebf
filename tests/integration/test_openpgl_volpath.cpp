// Issue 19: `openpgl_volpath`, Intel Open PGL's directional guiding driven as Blender Cycles
// drives it (src/volguide/integrators/openpgl/). Built whenever Open PGL is (CI builds it from
// ../shared/third_party); without it every test here but the availability check is SKIPPED, with
// the reason, and the availability check verifies the error a scene naming it gets.
//  - the media white furnace (heterogeneous, g = 0.9): every pixel has mean 1 although the field
//    is trained online and guides the phase sampling from the second pass on;
//  - per pixel against volpath on the benchmark scenes `shafts` and `cloud` (two independent renders
//    with their own per-sample variances, Šidák-corrected z-tests as in GuidedVsVolpathScenes);
//  - the same seed gives the same image for 1 and 2 threads: Open PGL's training runs with
//    deterministic = true (regions sort their samples before fitting), so the samples' arrival
//    order from the threads does not matter.
//  - untrained (training_spp = 0) it renders volpath's image bit for bit (the policy's unguided path
//    draws exactly volpath's random numbers).
//  - vsp=true (issue 37, Open PGL 0.8 only: cmake -DVOLGUIDE_OPENPGL_SOURCE=0.8): the furnace and the
//    two-sample test against volpath on shafts (chromatic homogeneous fog, the closed-form segment
//    decision) and cloud (a grid, the resampled one), each also checking from the render's statistics
//    that Open PGL's VSP decided a share of the segments; with 0.7.1, vsp=true is an error naming the
//    linked version.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

#include "support/bench_two_sample.h"
#include "support/cli.h"
#include "support/furnace_grid.h"
#include "support/test_support.h"
#include "support/volpath_test_util.h"
#include "volguide/render/image_io.h"

using namespace volguide;
using namespace volguide::test;

namespace {

#if VOLGUIDE_HAVE_OPENPGL
#define REQUIRE_OPENPGL() (void)0
#else
#define REQUIRE_OPENPGL() GTEST_SKIP() << "volguide was built without Intel Open PGL: openpgl_volpath is not available"
#endif

// Whether the linked Open PGL has the VSP API: cmake/openpgl.cmake builds 0.8 with it, 0.7.1 has none.
#if VOLGUIDE_HAVE_OPENPGL
bool openpgl_test_has_vsp() { return std::string(VOLGUIDE_OPENPGL_VERSION).rfind("0.7", 0) != 0; }
#define REQUIRE_OPENPGL_VSP()                                                                                    \
    if (!openpgl_test_has_vsp())                                                                                 \
    GTEST_SKIP() << "vsp=true needs Open PGL 0.8 (cmake -DVOLGUIDE_OPENPGL_SOURCE=0.8); this build links " \
                 << VOLGUIDE_OPENPGL_VERSION
#else
#define REQUIRE_OPENPGL_VSP() REQUIRE_OPENPGL()
#endif

// The integrator counters of a --stats file (openpgl_volpath's statistics()).
nlohmann::json openpgl_test_counters(const std::string& stats_file) {
    std::ifstream f(stats_file);
    return nlohmann::json::parse(f)["integrator"];
}

// openpgl_volpath (training_spp below the render's spp, so both trained and training passes are
// in the image; `params`: further integrator XML) against volpath, per pixel-channel and in the image
// mean. Returns the openpgl render's integrator counters.
nlohmann::json compare_with_volpath(const std::string& scene, int spp_volpath, int spp_openpgl, int training_spp,
                                    const std::string& params = "") {
    TempDir dir("openpgl-vs-volpath-" + scene);
    const BenchRender v = render_bench_scene(dir, scene, "volpath", spp_volpath, 11, {"-D", "integrator=volpath"});
    const std::string xml = dir.write(
        "openpgl.xml",
        fmt::format(R"(<scene version="3.0.0"><integrator type="openpgl_volpath">)"
                    R"(<integer name="max_depth" value="$max_depth"/><integer name="training_spp" value="{}"/>{})"
                    R"(</integrator></scene>)",
                    training_spp, params));
    const BenchRender g = render_bench_scene(dir, scene, "openpgl", spp_openpgl, 12,
                                             {"-D", "integrator_xml=" + xml, "--stats", dir.file("openpgl.json")});
    expect_same_expectation(v, g, scene, "volpath", "openpgl");
    return openpgl_test_counters(dir.file("openpgl.json"));
}

// vsp=true decided a share of the segments with Open PGL's VSP (else its tests would test free flight).
void expect_vsp_used(const nlohmann::json& counters) {
    ASSERT_TRUE(counters.contains("openpgl_vsp_decision_fraction")) << counters.dump();
    EXPECT_GT(counters["openpgl_vsp_decision_fraction"].get<double>(), 0.05) << counters.dump();
    EXPECT_GT(counters["openpgl_vsp_scatter_fraction"].get<double>(), 0.0) << counters.dump();
}

// The furnace of test_volpath_furnace_media.cpp's HeterogeneousForwardNull (a grid medium of albedo 1
// in a null sphere under a constant white sky) with the openpgl_volpath parameters `params`.
std::string openpgl_furnace_xml(const std::string& grid, const std::string& params) {
    return fmt::format(R"(<scene version="3.0.0">
    <integrator type="moment"><integrator type="openpgl_volpath">{}</integrator></integrator>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <medium type="heterogeneous" id="m">
        <volume type="gridvolume" name="sigma_t"><string name="filename" value="{}"/>
            <transform name="to_world"><scale value="2"/><translate value="-1, -1, -1"/></transform></volume>
        <rgb name="albedo" value="1"/>
        <phase type="hg"><float name="g" value="0.9"/></phase>
    </medium>
    <shape type="sphere"><bsdf type="null"/><ref name="interior" id="m"/></shape>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="12"/><integer name="height" value="12"/>
            <rfilter type="box"/></film>
    </sensor>
</scene>)",
                       params, grid);
}

}  // namespace

TEST(OpenPglVolpath, AvailabilityIsReported) {
    const CliResult version = run_cli({"--version"});
    EXPECT_EQ(version.exit_code, 0) << version.err;
#if VOLGUIDE_HAVE_OPENPGL
    EXPECT_NE(version.out.find("Intel Open PGL " VOLGUIDE_OPENPGL_VERSION ": built in"), std::string::npos)
        << version.out;
#else
    EXPECT_NE(version.out.find("Intel Open PGL: not built in"), std::string::npos) << version.out;
    // A scene naming the integrator fails with its file and line.
    TempDir dir("openpgl-missing");
    const std::string scene = dir.write("scene.xml", R"(<scene version="3.0.0">
    <integrator type="openpgl_volpath"/>
</scene>)");
    const CliResult r = run_cli({"render", scene, "-o", dir.file("x.exr"), "--quiet"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find(scene + ":2:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("built without Intel Open PGL"), std::string::npos) << r.err;
#endif
}

// The furnace of test_volpath_furnace_media.cpp's HeterogeneousForwardNull with openpgl_volpath
// (training_spp 64 of 256: the guided passes dominate the image).
TEST(OpenPglVolpath, HeterogeneousForwardFurnaceIsOne) {
    REQUIRE_OPENPGL();
    TempDir dir("openpgl-furnace");
    const std::string grid = write_furnace_grid(dir);
    const std::string xml = openpgl_furnace_xml(grid, R"(<integer name="training_spp" value="64"/>)");
    Rendered r = render_scene_xml(xml, 256, 17, /*test_media=*/false);
    expect_constant_image(r, 1.0);
}

// The same furnace with vsp=true: segments leaving guided vertices are decided with Open PGL's VSP
// by resampling the grid's tentative collisions; every pixel still has mean 1.
TEST(OpenPglVolpath, VspHeterogeneousForwardFurnaceIsOne) {
    REQUIRE_OPENPGL_VSP();
    TempDir dir("openpgl-vsp-furnace");
    const std::string grid = write_furnace_grid(dir);
    const std::string scene = dir.write(
        "scene.xml", openpgl_furnace_xml(grid, R"(<integer name="training_spp" value="64"/><boolean name="vsp" value="true"/>)"));
    const CliResult run = run_cli({"render", scene, "--spp", "256", "--seed", "17", "--variance", "--quiet", "-o",
                                   dir.file("f.exr"), "--stats", dir.file("f.json")});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const Rendered r = {read_image(dir.file("f.exr")), read_image(dir.file("f_var.exr")), 256};
    expect_constant_image(r, 1.0);
    expect_vsp_used(openpgl_test_counters(dir.file("f.json")));
}

// vsp=true against volpath: chromatic homogeneous fog (the closed-form segment decision with
// spectral MIS) and a grid cloud (the resampled one).
TEST(OpenPglVolpath, VspMatchesVolpathOnShafts) {
    REQUIRE_OPENPGL_VSP();
    expect_vsp_used(compare_with_volpath("shafts", 1024, 512, 64, R"(<boolean name="vsp" value="true"/>)"));
}

TEST(OpenPglVolpath, VspMatchesVolpathOnCloud) {
    REQUIRE_OPENPGL_VSP();
    expect_vsp_used(compare_with_volpath("cloud", 1024, 512, 64, R"(<boolean name="vsp" value="true"/>)"));
}

// With an Open PGL without the VSP API (0.7.1), vsp=true fails at the parameter's line, naming the
// linked version and the option that selects 0.8.
TEST(OpenPglVolpath, VspWithoutTheApiNamesTheVersion) {
    REQUIRE_OPENPGL();
#if VOLGUIDE_HAVE_OPENPGL
    if (openpgl_test_has_vsp()) GTEST_SKIP() << "this build links Open PGL " << VOLGUIDE_OPENPGL_VERSION << " (has VSP)";
    TempDir dir("openpgl-vsp-missing");
    const std::string scene = dir.write("scene.xml", R"(<scene version="3.0.0">
    <integrator type="openpgl_volpath">
        <boolean name="vsp" value="true"/>
    </integrator>
</scene>)");
    const CliResult r = run_cli({"render", scene, "-o", dir.file("x.exr"), "--quiet"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find(scene + ":3:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("Open PGL " VOLGUIDE_OPENPGL_VERSION), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("VOLGUIDE_OPENPGL_SOURCE=0.8"), std::string::npos) << r.err;
#endif
}

TEST(OpenPglVolpath, MatchesVolpathOnShafts) {
    REQUIRE_OPENPGL();
    compare_with_volpath("shafts", 1024, 512, 64);
}

TEST(OpenPglVolpath, MatchesVolpathOnCloud) {
    REQUIRE_OPENPGL();
    compare_with_volpath("cloud", 1024, 512, 64);
}

namespace {

// Same seed, 1 and 2 threads: bit-identical images (training included); `xml_text`: an integrator
// file (empty: openpgl_volpath's defaults).
void expect_openpgl_thread_independent(const std::string& xml_text) {
    TempDir dir("openpgl-threads");
    const std::vector<std::string> opgl =
        xml_text.empty() ? std::vector<std::string>{"-D", "integrator=openpgl_volpath"}
                         : std::vector<std::string>{"-D", "integrator_xml=" + dir.write("openpgl.xml", xml_text)};
    std::vector<std::string> one = opgl, two = opgl;
    one.insert(one.end(), {"--threads", "1"});
    two.insert(two.end(), {"--threads", "2"});
    const BenchRender a = render_bench_scene(dir, "shafts", "one", 32, 5, one);
    const BenchRender b = render_bench_scene(dir, "shafts", "two", 32, 5, two);
    ASSERT_EQ(a.mean.pixels.size(), b.mean.pixels.size());
    long differ = 0;
    for (size_t i = 0; i < a.mean.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) differ += a.mean.pixels[i][c] != b.mean.pixels[i][c];
    EXPECT_EQ(differ, 0) << "pixel-channels differing between --threads 1 and --threads 2";
}

}  // namespace

TEST(OpenPglVolpath, SameSeedSameImageForAnyThreadCount) {
    REQUIRE_OPENPGL();
    expect_openpgl_thread_independent("");
}

TEST(OpenPglVolpath, VspSameSeedSameImageForAnyThreadCount) {
    REQUIRE_OPENPGL_VSP();
    expect_openpgl_thread_independent(
        R"(<scene version="3.0.0"><integrator type="openpgl_volpath"><integer name="max_depth" value="$max_depth"/>)"
        R"(<boolean name="vsp" value="true"/></integrator></scene>)");
}

// Without training (training_spp = 0) the field never guides, and the policy draws exactly the
// random numbers volpath's walk draws: the image is volpath's, bit for bit.
TEST(OpenPglVolpath, UntrainedIsVolpathBitForBit) {
    REQUIRE_OPENPGL();
    TempDir dir("openpgl-untrained");
    const std::string xml = dir.write(
        "openpgl.xml", R"(<scene version="3.0.0"><integrator type="openpgl_volpath">)"
                       R"(<integer name="max_depth" value="$max_depth"/><integer name="training_spp" value="0"/>)"
                       R"(</integrator></scene>)");
    const BenchRender a = render_bench_scene(dir, "shafts", "volpath", 16, 3, {"-D", "integrator=volpath"});
    const BenchRender b = render_bench_scene(dir, "shafts", "openpgl", 16, 3, {"-D", "integrator_xml=" + xml});
    ASSERT_EQ(a.mean.pixels.size(), b.mean.pixels.size());
    long differ = 0;
    for (size_t i = 0; i < a.mean.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) differ += a.mean.pixels[i][c] != b.mean.pixels[i][c];
    EXPECT_EQ(differ, 0) << "pixel-channels differing from volpath";
}
