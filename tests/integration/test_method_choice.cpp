// guided_volpath's measured per-tile method choice and staged pre-pass (issue 55; integrators/guided/
// estimates/method_choice.h, guided_volpath.h):
//  - the combined image (some tiles guided, some bounded volpath) has volpath's mean, on a dense sphere
//    and on a lit fog room, with the map the probes chose and with a checkerboard map forced through the
//    pre-pass state (so both methods certainly render tiles of one image);
//  - the pre-pass state carries the map: a render from it uses the same map;
//  - a scene where guiding cannot pay stops training after the coarse stage (choice_stage 1, every tile
//    volpath's), one where it pays trains the full field (choice_stage 2);
//  - under --time the pre-pass keeps within training_fraction of the budget (the schedule's limit in the
//    statistics; the measured time with a generous margin: real figures are in bench/RESULTS.md).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <map>

#include "support/volpath_test_util.h"
#include "volguide/integrators/guided/guided_volpath.h"
#include "volguide/integrators/guided/prepass/guided_prepass.h"
#include "volguide/integrators/moment.h"

using namespace volguide;
using namespace volguide::test;

namespace {

const char* kGuidedDefaults =
    R"(<integrator type="guided_volpath"><boolean name="method_choice" value="true"/><integer name="photons" value="100000"/><integer name="leaf_samples" value="400"/></integrator>)";
const char* kVolpath = R"(<integrator type="volpath"/>)";

// A sphere of dense, bright medium (sigma_t 8, albedo 0.95) lit by an area light from behind and the side:
// the dense-sphere benchmark's situation in miniature. `res` x `res` pixels.
std::string dense_sphere_xml(const std::string& integrator, int res) {
    return fmt::format(R"(<scene version="3.0.0">
    <integrator type="moment">{}</integrator>
    <medium type="homogeneous" id="m">
        <rgb name="sigma_t" value="8, 6, 10"/>
        <rgb name="albedo" value="0.95, 0.9, 0.85"/>
        <phase type="hg"><float name="g" value="0.3"/></phase>
    </medium>
    <shape type="sphere"><bsdf type="null"/><ref name="interior" id="m"/></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="1.5"/><rotate y="1" angle="150"/><translate value="2, 1, -2.5"/></transform>
        <emitter type="area"><rgb name="radiance" value="6"/></emitter>
    </shape>
    <emitter type="constant"><rgb name="radiance" value="0.05"/></emitter>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="{}"/><integer name="height" value="{}"/>
            <rfilter type="box"/></film>
    </sensor>
</scene>)",
                       integrator, res, res);
}

// A room-sized box of thin fog over a diffuse floor, lit by a point light through the fog: the fog room.
std::string fog_room_xml(const std::string& integrator, int res) {
    return fmt::format(R"(<scene version="3.0.0">
    <integrator type="moment">{}</integrator>
    <medium type="homogeneous" id="fog">
        <rgb name="sigma_t" value="0.6, 0.3, 0.9"/>
        <rgb name="albedo" value="0.9, 0.8, 0.7"/>
        <phase type="hg"><float name="g" value="0.6"/></phase>
    </medium>
    <shape type="cube"><bsdf type="null"/><ref name="interior" id="fog"/></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/><translate y="-1.01"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    </shape>
    <emitter type="point"><point name="position" value="1.6, 0.3, 0"/><rgb name="intensity" value="8"/></emitter>
    <sensor type="perspective">
        <float name="fov" value="50"/>
        <transform name="to_world"><lookat origin="-0.5, 0.8, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="{}"/><integer name="height" value="{}"/>
            <rfilter type="box"/></film>
    </sensor>
</scene>)",
                       integrator, res, res);
}

const GuidedVolPathIntegrator& guided_of(const Scene& scene) {
    return dynamic_cast<const GuidedVolPathIntegrator&>(dynamic_cast<const MomentIntegrator&>(scene.integrator()).nested());
}

std::map<std::string, double> stats_of(const Scene& scene) {
    std::map<std::string, double> out;
    for (const auto& [k, v] : guided_of(scene).statistics()) out[k] = v;
    return out;
}

struct ChoiceRender {
    Rendered image;
    ChoiceMap map;
    std::map<std::string, double> stats;
    std::string prepass;
};

// Renders `xml` (guided_volpath inside moment) at `spp`; `prepass` non-empty: from that pre-pass state.
ChoiceRender render_guided(const std::string& xml, int spp, uint64_t seed, const std::string& prepass = "",
                           double time_budget = 0) {
    TempDir dir("method-choice");
    auto scene = load_scene(dir.write("s.xml", xml));
    Integrator& integrator = const_cast<Integrator&>(scene->integrator());
    if (!prepass.empty()) integrator.use_prepass_state(prepass);
    RenderOptions ro;
    ro.spp = spp;
    ro.seed = seed;
    ro.time_budget = time_budget;
    RenderResult r = render(*scene, ro);
    return {{r.mean, r.variance, r.spp}, guided_of(*scene).choice_map(), stats_of(*scene), integrator.prepass_state()};
}

// The pre-pass state with its map replaced by a checkerboard of tiles.
std::string with_checkerboard(const std::string& prepass, int width, int height) {
    GuidedPrepass p = deserialize_guided_prepass(prepass);
    ChoiceMap map{width, height, {}};
    for (int ty = 0; ty < map.tiles_y(); ++ty)
        for (int tx = 0; tx < map.tiles_x(); ++tx)
            map.tiles.push_back((tx + ty) % 2 ? TileMethod::Volpath : TileMethod::Guided);
    return serialize_guided_prepass(p.field, p.pixel_estimate, p.selection, map.serialize());
}

}  // namespace

TEST(MethodChoice, CombinedImageHasVolpathsMeanOnADenseSphere) {
    const Rendered ref = render_scene_xml(dense_sphere_xml(kVolpath, 32), 1024, 3, false);
    const ChoiceRender chosen = render_guided(dense_sphere_xml(kGuidedDefaults, 32), 512, 4);
    ASSERT_FALSE(chosen.map.empty());
    EXPECT_EQ(chosen.map.tiles.size(), 4u);
    expect_same_means(chosen.image, ref);
    const ChoiceRender forced =
        render_guided(dense_sphere_xml(kGuidedDefaults, 32), 512, 5, with_checkerboard(chosen.prepass, 32, 32));
    ASSERT_NEAR(forced.map.volpath_share(), 0.5, 1e-12);  // the given map is the one rendered
    expect_same_means(forced.image, ref);
}

TEST(MethodChoice, CombinedImageHasVolpathsMeanInAFogRoom) {
    const Rendered ref = render_scene_xml(fog_room_xml(kVolpath, 32), 1024, 6, false);
    const ChoiceRender chosen = render_guided(fog_room_xml(kGuidedDefaults, 32), 512, 7);
    ASSERT_FALSE(chosen.map.empty());
    expect_same_means(chosen.image, ref);
    const ChoiceRender forced =
        render_guided(fog_room_xml(kGuidedDefaults, 32), 512, 8, with_checkerboard(chosen.prepass, 32, 32));
    ASSERT_NEAR(forced.map.volpath_share(), 0.5, 1e-12);
    expect_same_means(forced.image, ref);
}

// The pre-pass state carries the map: rendering from it gives the map and the image of the render that
// trained it (same seed and spp).
TEST(MethodChoice, ThePrepassStateCarriesTheMap) {
    const ChoiceRender trained = render_guided(dense_sphere_xml(kGuidedDefaults, 48), 16, 9);
    ASSERT_FALSE(trained.map.empty());
    EXPECT_FALSE(deserialize_guided_prepass(trained.prepass).choice.empty());
    const ChoiceRender given = render_guided(dense_sphere_xml(kGuidedDefaults, 48), 16, 9, trained.prepass);
    EXPECT_EQ(given.map.tiles, trained.map.tiles);
    EXPECT_TRUE(given.image.mean.pixels == trained.image.mean.pixels);
}

// A scene where guiding cannot pay: a dense sphere under a uniform sky (nothing directional to guide
// towards; every guided vertex costs more) stops after the coarse stage with every tile volpath's; the
// dense sphere lit from behind trains the full field.
std::string uniform_sphere_xml(int res) {
    return fmt::format(R"(<scene version="3.0.0">
    <integrator type="moment">{}</integrator>
    <medium type="homogeneous" id="m">
        <rgb name="sigma_t" value="10"/><rgb name="albedo" value="0.8"/><phase type="isotropic"/>
    </medium>
    <shape type="sphere"><bsdf type="null"/><ref name="interior" id="m"/></shape>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <sensor type="perspective">
        <float name="fov" value="20"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="{}"/><integer name="height" value="{}"/>
            <rfilter type="box"/></film>
    </sensor>
</scene>)",
                       kGuidedDefaults, res, res);
}

TEST(MethodChoice, TrainingStopsEarlyWhereGuidingCannotPay) {
    const ChoiceRender uniform = render_guided(uniform_sphere_xml(48), 256, 1);  // 16 probe rounds
    EXPECT_EQ(uniform.stats.at("choice_stage"), 1.0);
    EXPECT_EQ(uniform.stats.at("choice_volpath_share"), 1.0);
    EXPECT_LE(uniform.stats.at("photons_traced"), 100000 / 8);  // the coarse field's photons only
    const ChoiceRender dense = render_guided(dense_sphere_xml(kGuidedDefaults, 48), 64, 10);
    EXPECT_EQ(dense.stats.at("choice_stage"), 2.0);
    EXPECT_LT(dense.stats.at("choice_volpath_share"), 1.0);
}

// Under --time the pre-pass's limit is training_fraction of the budget, and the pre-pass keeps to it
// (a generous margin: the machine may be loaded; bench/RESULTS.md has the measured figures).
TEST(MethodChoice, PrepassKeepsWithinItsShareOfATimeBudget) {
    TempDir dir("method-choice-time");
    auto scene = load_scene(dir.write("s.xml", dense_sphere_xml(kGuidedDefaults, 64)));
    RenderOptions ro;
    ro.seed = 11;
    ro.time_budget = 4.0;
    const RenderResult r = render(*scene, ro);
    const auto stats = stats_of(*scene);
    EXPECT_DOUBLE_EQ(stats.at("preprocess_limit_seconds"), 1.0);  // training_fraction 0.25 of 4 s
    EXPECT_LT(r.stats.preprocess_seconds, 2.0 * 1.0);
    EXPECT_GT(r.spp, 0);
}
