// rrs=ears (issue 38, docs/theory.md §9.8): efficiency-aware RR and splitting from the render's own
// statistics, at medium vertices and at diffuse surface vertices, stays unbiased: the white furnace stays 1, and a dense high-albedo sphere and a fog sphere
// inside a rough dielectric in a Cornell-like box (bench/scenes/glassfog.xml at 12 x 9) match volpath's
// mean; and it really decides (roulette, splitting, learned points) within its branch budget.
// ears_min_samples is lowered so that a short render learns cells after its first passes.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <map>
#include <string>

#include "support/test_support.h"
#include "support/volpath_test_util.h"
#include "volguide/integrators/moment.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// guided_volpath with rrs=ears; `guide`: the distance and direction decisions (XML).
std::string ears_integrator(const std::string& guide, const std::string& extra = "") {
    return fmt::format(R"(<integrator type="guided_volpath">{}<string name="rrs" value="ears"/>
        <integer name="ears_min_samples" value="8"/><integer name="max_depth" value="64"/>
        <integer name="photons" value="100000"/><integer name="leaf_samples" value="400"/>{}</integrator>)",
                       guide, extra);
}
const char* kGuided = R"(<string name="distance" value="incremental"/><string name="direction" value="product"/>)";
const char* kUnguided = R"(<string name="distance" value="standard"/><string name="direction" value="phase"/>)";

std::string sensor_xml(const std::string& origin, float fov, int w, int h) {
    return fmt::format(R"(<sensor type="perspective"><float name="fov" value="{}"/>
        <transform name="to_world"><lookat origin="{}" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="{}"/><integer name="height" value="{}"/>
            <rfilter type="box"/></film></sensor>)",
                       fov, origin, w, h);
}

std::string ears_furnace_xml(const std::string& integrator) {
    return R"(<scene version="3.0.0"><integrator type="moment">)" + integrator + R"(</integrator>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <medium type="homogeneous" id="m"><rgb name="sigma_t" value="2, 1, 3"/><rgb name="albedo" value="1"/>
        <phase type="hg"><float name="g" value="0.9"/></phase></medium>
    <shape type="sphere"><bsdf type="null"/><ref name="interior" id="m"/></shape>)" +
           sensor_xml("0, 0, 4", 45.f, 12, 12) + "</scene>";
}

// densesphere's medium (sigma_t 8, albedo 0.995, g 0.6) back-lit by an area light, on a floor.
std::string ears_dense_sphere_xml(const std::string& integrator) {
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
           sensor_xml("0, 0.3, 5", 40.f, 12, 12) + "</scene>";
}

// bench/scenes/glassfog.xml at 12 x 9 with `integrator` inside `moment`.
std::string glassfog_xml(TempDir& dir, const std::string& integrator) {
    const std::string file = dir.write("integrator.xml", R"(<scene version="3.0.0"><integrator type="moment">)" +
                                                             integrator + "</integrator></scene>");
    return fmt::format(R"(<scene version="3.0.0"><default name="width" value="12"/><default name="height" value="9"/>
        <default name="integrator_xml" value="{}"/><include filename="{}/bench/scenes/glassfog.xml"/></scene>)",
                       file, source_dir());
}

struct StatsRender {
    Rendered image;
    std::map<std::string, double> stats;
};
StatsRender render_with_stats(const std::string& xml, int spp, uint64_t seed) {
    TempDir dir("ears-render");
    auto scene = load_scene(dir.write("s.xml", xml));
    RenderOptions ro;
    ro.spp = spp;
    ro.seed = seed;
    RenderResult r = render(*scene, ro);
    StatsRender out{{r.mean, r.variance, r.spp}, {}};
    const auto& moment = dynamic_cast<const MomentIntegrator&>(scene->integrator());
    for (const auto& [k, v] : moment.nested().statistics()) out.stats[k] = v;
    return out;
}

// EARS made decisions from learned points (and killed paths, `roulette`), within the cap.
void expect_ears_decided(const std::map<std::string, double>& s, bool roulette = true) {
    ASSERT_TRUE(s.count("ears_learned_points"));
    EXPECT_GT(s.at("ears_learned_points"), 0.0);
    EXPECT_GT(s.at("ears_image_relative_variance"), 0.0);
    EXPECT_GT(s.at("rrs_decisions"), 0.0);
    if (roulette) {
        EXPECT_GT(s.at("rrs_kills"), 0.0);
    }
    EXPECT_GT(s.at("rrs_unlearned"), 0.0);  // the first passes, before any statistics
    EXPECT_LE(s.at("rrs_branches_max"), 64.0);
    EXPECT_EQ(s.at("rrs_cap_hits"), 0.0);
    EXPECT_EQ(s.at("rrs_cap_limited"), 0.0);
}

}  // namespace

TEST(Ears, WhiteFurnaceStaysOne) {
    for (const char* guide : {kGuided, kUnguided}) {
        SCOPED_TRACE(guide);
        const StatsRender r = render_with_stats(ears_furnace_xml(ears_integrator(guide)), 1024, 21);
        expect_constant_image(r.image, 1.0);
        // Every path collects 1 per unit weight in a pixel of value 1: little to roulette.
        expect_ears_decided(r.stats, false);
        EXPECT_GT(r.stats.at("rrs_splits"), 0.0);
    }
}

TEST(Ears, DenseSphereMatchesVolpath) {
    Rendered ref = render_scene_xml(
        ears_dense_sphere_xml(R"(<integrator type="volpath"><integer name="max_depth" value="64"/></integrator>)"), 1024,
        5, false);
    for (const char* guide : {kGuided, kUnguided}) {
        SCOPED_TRACE(guide);
        const StatsRender g = render_with_stats(ears_dense_sphere_xml(ears_integrator(guide)), 1024, 6);
        expect_same_means(g.image, ref);
        expect_ears_decided(g.stats);
        // The diffuse floor's vertices decide too (the surface stage, docs/theory.md §9.8).
        EXPECT_GT(g.stats.at("ears_learned_surface_points"), 0.0);
    }
}

// Surfaces only: a diffuse sphere on a diffuse floor under a sky, where every decision is the surface
// stage's (no medium: the field has no leaf, the statistics' cell is the one outside it).
std::string ears_diffuse_xml(const std::string& integrator) {
    return R"(<scene version="3.0.0"><integrator type="moment">)" + integrator + R"(</integrator>
    <shape type="sphere"><bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="6"/><rotate x="1" angle="-90"/><translate y="-1"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.7"/></bsdf></shape>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>)" +
           sensor_xml("0, 1, 4", 50.f, 12, 12) + "</scene>";
}

TEST(Ears, DiffuseSurfacesMatchVolpath) {
    Rendered ref = render_scene_xml(
        ears_diffuse_xml(R"(<integrator type="volpath"><integer name="max_depth" value="64"/></integrator>)"), 1024, 9,
        false);
    const StatsRender g = render_with_stats(ears_diffuse_xml(ears_integrator(kUnguided)), 1024, 10);
    expect_same_means(g.image, ref);
    expect_ears_decided(g.stats, false);
    EXPECT_GT(g.stats.at("ears_learned_surface_points"), 0.0);
    EXPECT_EQ(g.stats.at("ears_learned_surface_points"), g.stats.at("ears_learned_points"));
}

TEST(Ears, FogInRoughDielectricMatchesVolpath) {
    TempDir dir("ears-glassfog");
    Rendered ref = render_scene_xml(
        glassfog_xml(dir, R"(<integrator type="volpath"><integer name="max_depth" value="64"/></integrator>)"), 1024,
        7, false);
    TempDir dir2("ears-glassfog-g");
    const StatsRender g = render_with_stats(glassfog_xml(dir2, ears_integrator(kGuided)), 1024, 8);
    expect_same_means(g.image, ref);
    expect_ears_decided(g.stats);
    EXPECT_GT(g.stats.at("ears_learned_surface_points"), 0.0);  // the box's diffuse walls
}

// A fixed budget bounds every camera sample's branches by construction; ears' fallback is the bounded
// throughput roulette unless rr_rule is given.
TEST(Ears, FixedBudgetAndSettings) {
    const StatsRender r = render_with_stats(
        ears_furnace_xml(ears_integrator(kGuided, R"(<float name="rrs_branch_budget" value="2"/>)")), 256, 22);
    EXPECT_LE(r.stats.at("rrs_branches_max"), 2.0);
    EXPECT_EQ(r.stats.at("ears_branch_budget"), 2.0);
    TempDir dir("ears-settings");
    for (const char* bad : {R"(<string name="rrs" value="grrs"/><integer name="ears_min_samples" value="8"/>)",
                            R"(<string name="rrs" value="ears"/><float name="rrs_window" value="5"/>)",
                            R"(<string name="rrs" value="ears"/><integer name="ears_min_samples" value="1"/>)",
                            R"(<string name="rrs" value="grrs"/><float name="ears_budget_factor" value="2"/>)"}) {
        SCOPED_TRACE(bad);
        const std::string xml = ears_furnace_xml(std::string(R"(<integrator type="guided_volpath">)") + bad + "</integrator>");
        EXPECT_THROW(load_scene(dir.write("bad.xml", xml)), std::exception);
    }
}
