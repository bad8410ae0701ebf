// guided_volpath's guided decisions (issue 7) do not change the expectation:
//  - white furnace (oracles.md §1): a constant environment of radiance 1 around a sphere of an
//    albedo-1 forward-scattering (g = 0.9) medium, chromatic homogeneous and heterogeneous, behind a
//    null boundary: every distance x direction combination (heterogeneous: incremental = guided
//    tracking) gives 1 in every pixel (image mean
//    within 4 standard errors, 6x6 blocks within 5: expect_constant_image) at 1024 spp — at 256 spp
//    incident-only guiding (g = 0.9, dense heterogeneous) under-reads blocks by ~10 % (5 SE): its
//    weights f_p / p are heavy-tailed over long paths; 4096 spp converge to 1 (measured);
//  - with c_T = 1 (transmittance strategies only) and albedo 1, every guided distance sample has
//    weight exactly 1, query after query (the sampler's per-thread scratch carries no state);
//  - a point light in chromatic fog with a diffuse floor (light arriving from one side, so the
//    guided probabilities are far from the unguided ones): the image means of guided renders agree
//    with volpath's (two-sample z-test per channel), homogeneous and heterogeneous;
//    The floor is guided too (surface_guiding, from the fog's leaves above it) whenever the
//    direction is (standard/product and incremental/product);
//  - the guide's statistics show that it was really used (guided strategies, stepped bins; guided
//    null-collision tracking in heterogeneous media; guided floor vertices);
//  - guided RR and splitting (issue 8, docs/theory.md §9): the same furnace and lit fog with rrs=grr and
//    rrs=grrs (windows s = 1 and 5, with and without guided sampling), and its statistics (kills,
//    splits, the branch cap);
//  - the field refined during the render (refine_passes) against volpath's mean.
#include <limits>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "support/furnace_grid.h"
#include "support/volpath_test_util.h"
#include "volguide/core/warp.h"
#include "volguide/integrators/guided/guided_volpath.h"
#include "volguide/integrators/moment.h"
#include "volguide/integrators/guided/walk/guided_continuation.h"
#include "volguide/integrators/guided/walk/guided_vertex.h"
#include "volguide/integrators/guided/walk/walk_guide.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// A distance decision that is not a camera segment's (no pixel buffer P_G).
constexpr float kNoCameraBuffer = std::numeric_limits<float>::quiet_NaN();

std::string sigma_t_xml(bool heterogeneous, const std::string& grid, float scale) {
    return heterogeneous
               ? fmt::format(R"(<volume type="gridvolume" name="sigma_t"><string name="filename" value="{}"/>
                 <transform name="to_world"><scale value="2"/><translate value="-1, -1, -1"/></transform></volume>
                 <float name="scale" value="{}"/>)",
                             grid, scale)
               : fmt::format(R"(<rgb name="sigma_t" value="{}, {}, {}"/>)", 2.f * scale, 1.f * scale,
                             3.f * scale);
}

// leaf_tau_max < 0: the default.
// `extra`: more parameters, as XML.
// `rrs`: the RR/splitting parameters, as XML.
// The decisions as configured, everywhere (allocation=false: what these tests exercise), unless `extra`
// sets the allocation itself (issue 59's tests).
std::string guided(const std::string& distance, const std::string& direction, int photons,
                   float leaf_tau_max = -1.f, const std::string& extra = "",
                   const std::string& rrs = R"(<string name="rrs" value="standard"/>)") {
    const std::string configured =
        extra.find(R"(name="allocation")") == std::string::npos ? R"(<boolean name="allocation" value="false"/>)" : "";
    return fmt::format(R"(<integrator type="guided_volpath"><string name="distance" value="{}"/>
        <string name="direction" value="{}"/>{}
        <integer name="photons" value="{}"/><integer name="leaf_samples" value="400"/>{}{}{}</integrator>)",
                       distance, direction, rrs, photons,
                       leaf_tau_max < 0.f
                           ? std::string()
                           : fmt::format(R"(<float name="leaf_tau_max" value="{}"/>)", leaf_tau_max),
                       extra, configured);
}

std::string guided_furnace_xml(bool heterogeneous, const std::string& grid, const std::string& integrator) {
    return fmt::format(R"(<scene version="3.0.0">
    <integrator type="moment">{}</integrator>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <medium type="{}" id="m">
        {}
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
                       integrator, heterogeneous ? "heterogeneous" : "homogeneous",
                       sigma_t_xml(heterogeneous, grid, 1.f));
}

// Fog in a box [-1, 1]^3 (null boundary) over a diffuse floor, a point light at the box's side.
std::string lit_fog_xml(bool heterogeneous, const std::string& grid, const std::string& integrator) {
    return fmt::format(R"(<scene version="3.0.0">
    <integrator type="moment">{}</integrator>
    <medium type="{}" id="fog">
        {}
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
        <film type="hdrfilm"><integer name="width" value="12"/><integer name="height" value="12"/>
            <rfilter type="box"/></film>
    </sensor>
</scene>)",
                       integrator, heterogeneous ? "heterogeneous" : "homogeneous",
                       sigma_t_xml(heterogeneous, grid, 0.3f));
}

struct Combo {
    const char* distance;
    const char* direction;
};
const Combo kCombos[] = {{"standard", "incident"}, {"standard", "product"}, {"incremental", "phase"},
                         {"incremental", "incident"}, {"incremental", "product"}};

// The guided integrator inside `moment`, for its statistics.
// The point-lit fog, homogeneous and heterogeneous, rendered at 1024 spp with `integrator` (seed
// `seed`), has volpath's image means (volpath at seed 7).
void expect_lit_fog_means_of_volpath(const std::string& grid, const std::string& integrator, uint64_t seed) {
    for (bool het : {false, true}) {
        SCOPED_TRACE(het ? "heterogeneous" : "homogeneous");
        Rendered ref = render_scene_xml(lit_fog_xml(het, grid, R"(<integrator type="volpath"/>)"), 1024, 7, false);
        Rendered g = render_scene_xml(lit_fog_xml(het, grid, integrator), 1024, seed, false);
        expect_same_means(g, ref);
    }
}

std::map<std::string, double> guide_stats(const std::string& xml, int spp = 4) {
    TempDir dir("guided-stats");
    auto scene = load_scene(dir.write("s.xml", xml));
    RenderOptions ro;
    ro.spp = spp;
    ro.seed = 3;
    render(*scene, ro);
    const auto& moment = dynamic_cast<const MomentIntegrator&>(scene->integrator());
    std::map<std::string, double> out;
    for (const auto& [k, v] : moment.nested().statistics()) out[k] = v;
    return out;
}

}  // namespace

TEST(GuidedVolPathUnbiased, WhiteFurnaceEveryCombination) {
    TempDir dir("guided-furnace");
    const std::string grid = write_furnace_grid(dir);
    for (bool het : {false, true})
        for (const Combo& c : kCombos) {
            SCOPED_TRACE(fmt::format("{} distance={} direction={}", het ? "heterogeneous" : "homogeneous",
                                     c.distance, c.direction));
            // Incident-only directions with guided tracking (heterogeneous): the 1024-spp image has one
            // block 5.8 SE low at seed 17 (0.934 +- 0.011), seeds 18, 19 and 4096 spp at seed 17 pass:
            // the heavy tail noted above, so this combination gets 4096 spp.
            const bool heavy =
                het && std::string(c.distance) == "incremental" && std::string(c.direction) == "incident";
            Rendered r = render_scene_xml(guided_furnace_xml(het, grid, guided(c.distance, c.direction, 100000)),
                                          heavy ? 4096 : 1024, 17, /*test_media=*/false);
            expect_constant_image(r, 1.0);
        }
    // Leaves "optically large": leaf_tau_max 0.4 damps bins and vertices toward free flight and the
    // phase function by factors around 1/2 (leaves ~0.3 across, sigma_t 2 on average); 0.02 makes
    // every vertex skip guiding (confidence < 1/4). Still 1.
    for (const float tau_max : {0.4f, 0.02f})
        for (const std::string distance : {"incremental", "vsp"}) {
            SCOPED_TRACE(fmt::format("leaf_tau_max {} {}", tau_max, distance));
            Rendered r = render_scene_xml(
                guided_furnace_xml(false, grid, guided(distance, "product", 100000, tau_max)), 1024, 18, false);
            expect_constant_image(r, 1.0);
        }
}

TEST(GuidedVolPathUnbiased, PointLitFogMatchesVolpath) {
    TempDir dir("guided-lit-fog");
    const std::string grid = write_furnace_grid(dir);
    for (bool het : {false, true}) {
        Rendered ref =
            render_scene_xml(lit_fog_xml(het, grid, R"(<integrator type="volpath"/>)"), 1024, 5, false);
        for (const Combo& c : {kCombos[1], kCombos[4]}) {
            SCOPED_TRACE(fmt::format("{} distance={} direction={}", het ? "heterogeneous" : "homogeneous",
                                     c.distance, c.direction));
            Rendered g = render_scene_xml(lit_fog_xml(het, grid, guided(c.distance, c.direction, 200000)),
                                          1024, 6, false);
            expect_same_means(g, ref);
        }
    }
}

// Issue 20: the distance walk over leaf groups (distance_merge) instead of single leaves
// (homogeneous media: heterogeneous ones use guided tracking): the furnace stays 1, and the point-lit
// fog matches volpath; the statistics show the groups were built.
TEST(GuidedVolPathUnbiased, DistanceRegionsAreUnbiased) {
    TempDir dir("guided-leaf-groups");
    const std::string grid = write_furnace_grid(dir);
    const std::string merge = R"(<float name="distance_merge" value="0.5"/>)";
    Rendered r = render_scene_xml(guided_furnace_xml(false, grid, guided("incremental", "product", 100000, -1.f, merge)),
                                  1024, 19, false);
    expect_constant_image(r, 1.0);
    Rendered ref = render_scene_xml(lit_fog_xml(false, grid, R"(<integrator type="volpath"/>)"), 1024, 5, false);
    Rendered g = render_scene_xml(lit_fog_xml(false, grid, guided("incremental", "product", 200000, -1.f, merge)),
                                  1024, 7, false);
    expect_same_means(g, ref);
    const auto s = guide_stats(lit_fog_xml(false, grid, guided("incremental", "product", 200000, -1.f, merge)));
    EXPECT_GT(s.at("leaf_groups"), 0.0);
}

TEST(GuidedVolPathUnbiased, TheGuideIsUsed) {
    TempDir dir("guided-used");
    const std::string grid = write_furnace_grid(dir);
    const auto s = guide_stats(lit_fog_xml(false, grid, guided("incremental", "product", 200000)));
    ASSERT_TRUE(s.count("distance_queries"));
    EXPECT_GT(s.at("distance_queries"), 100.0);
    EXPECT_GT(s.at("distance_average_steps"), 1.0);
    EXPECT_NEAR(s.at("distance_guided_fraction"), 0.5, 0.1);  // c_T = 0.5
    EXPECT_LT(s.at("distance_invalid_bin_fraction"), 0.5);
    EXPECT_GT(s.at("direction_guided_fraction"), 0.3);  // phase_prob 0.5, most leaves valid
    EXPECT_EQ(s.at("distance_nan_fallbacks"), 0.0);
    // The fog (sigma_t <= 0.27) in leaves smaller than the box: optically small, nothing damped by
    // default; with leaf_tau_max 0.01 every guided bin and vertex is.
    EXPECT_EQ(s.at("distance_damped_bin_fraction"), 0.0);
    EXPECT_EQ(s.at("direction_damped_vertex_fraction"), 0.0);
    const auto d = guide_stats(lit_fog_xml(false, grid, guided("incremental", "product", 200000, 0.01f)));
    EXPECT_GT(d.at("distance_damped_bin_fraction"), 0.5);  // the rest: outside the fog / invalid leaves
    EXPECT_GT(d.at("direction_damped_vertex_fraction"), 0.5);
    EXPECT_LT(d.at("direction_guided_fraction"), 0.25);  // phase_prob pushed toward 1
    EXPECT_GT(d.at("distance_skipped"), 0.0);            // queries from vertices of confidence < 1/4
    EXPECT_EQ(s.at("distance_skipped"), 0.0);
    // The diffuse floor 0.01 below the fog is guided by the leaves above it (surface_guiding,
    // default true) where they are mostly fog: the floor (6 x 6) is wider than the fog (2 x 2), and
    // the leaves along the fog's lower edges reach out over the bare floor (measured: 0.72 of the
    // floor vertices find a valid leaf, 0.15 one at least half filled with fog); about half of
    // the guided vertices' directions (bsdf_prob 0.5) come from the guide.
    EXPECT_GT(s.at("surface_vertices"), 100.0);
    EXPECT_GT(s.at("surface_guided_vertex_fraction"), 0.1);
    EXPECT_NEAR(s.at("surface_guided_sample_fraction") / s.at("surface_guided_vertex_fraction"), 0.5, 0.1);
    const auto off = guide_stats(lit_fog_xml(
        false, grid, guided("incremental", "product", 200000, -1.f, R"(<boolean name="surface_guiding" value="false"/>)")));
    EXPECT_EQ(off.at("surface_vertices"), 0.0);
    // direction=phase guides no directions, surfaces included.
    const auto phase = guide_stats(lit_fog_xml(false, grid, guided("incremental", "phase", 200000)));
    EXPECT_EQ(phase.at("surface_vertices"), 0.0);
}

TEST(GuidedVolPathUnbiased, HeterogeneousMediaUseGuidedTracking) {
    TempDir dir("guided-tracking-used");
    const std::string grid = write_furnace_grid(dir);
    const auto s = guide_stats(lit_fog_xml(true, grid, guided("incremental", "product", 200000)));
    EXPECT_EQ(s.at("distance_tracking_fraction"), 1.0);  // every query inside the fog
    EXPECT_EQ(s.at("distance_guided_fraction"), 0.0);    // no bin sampler
    EXPECT_GT(s.at("distance_average_steps"), 1.0);      // tentative collisions per query
    EXPECT_LT(s.at("distance_invalid_bin_fraction"), 0.5);
    EXPECT_EQ(s.at("distance_nan_fallbacks"), 0.0);
}

TEST(GuidedVolPathUnbiased, TransmittanceStrategiesAloneGiveUnitWeights) {
    TempDir dir("guided-unit-weights");
    std::string xml = guided_furnace_xml(false, "", guided("incremental", "phase", 100000));
    const std::string chromatic = R"(value="2, 1, 3")";
    xml.replace(xml.find(chromatic), chromatic.size(), R"(value="2")");  // grey: weights are exactly 1
    auto scene = load_scene(dir.write("s.xml", xml));
    auto& moment = dynamic_cast<MomentIntegrator&>(const_cast<Integrator&>(scene->integrator()));
    PreprocessContext ctx;
    ctx.seed = 1;
    moment.preprocess(*scene, ctx);
    const auto& integrator = dynamic_cast<const GuidedVolPathIntegrator&>(moment.nested());
    const Medium* medium = nullptr;
    for (const auto& shape : scene->shapes())
        if (shape->interior_medium()) medium = shape->interior_medium();
    ASSERT_NE(medium, nullptr);
    for (DistanceGuiding mode : {DistanceGuiding::Incremental, DistanceGuiding::Vsp}) {
        WalkGuideSettings ws;
        ws.distance = mode;
        ws.distance_settings.c_T = 1.f;
        const WalkGuide guide(*scene, integrator.field(), ws);
        WalkGuideStats counts;
        GuidedVertex origin(guide, counts);  // not begun: the rays leave from no vertex, as from the camera
        int scattered = 0;
        for (int i = 0; i < 2000; ++i) {
            Sampler s(9, 0, uint64_t(i));
            const Ray ray(Point3f(0.f), warp::square_to_uniform_sphere(s.next_2d()));
            const FreeFlightSample f =
                origin.sample_distance(DistanceQuery{*medium, ray, 0.999f, Color3(1.f)}, kNoCameraBuffer, s, nullptr);
            scattered += f.scattered;
            ASSERT_NEAR(f.weight.r, 1.f, 2e-4f) << "query " << i << (f.scattered ? " scattered" : " passed");
        }
        EXPECT_GT(scattered, 1000);  // 1 - exp(-2) of them
        if (mode == DistanceGuiding::Incremental)
            EXPECT_GT(counts.distance_steps, 2 * counts.distance_queries);  // several leaves per ray
        else
            EXPECT_GT(counts.vsp_queries, 1000u);
    }
}

// Issue 37: the per-vertex object (GuidedVertex) answers each decision from one leaf lookup and one
// product: the direction density of the mixture of the phase function and the leaf's guide (the
// product with the phase VMM; phase probability 1/2, damped by the leaf's confidence), the
// continuation's estimate (the trusted leaf's L~_i / L~), and a distance decision that leaves from it
// names its leaf as the decision's cell. It looks nothing up at init, descends once at most however
// often it is asked, and builds its direction mixture once. With c_T = 1, distance="vsp" from it is
// free flight: grey albedo-1 weights are exactly 1.
TEST(GuidedVolPathUnbiased, GuidedVertexAnswersEachDecisionFromOneLookup) {
    TempDir dir("guided-vertex");
    std::string xml = guided_furnace_xml(false, "", guided("vsp", "product", 100000));
    const std::string chromatic = R"(value="2, 1, 3")";
    xml.replace(xml.find(chromatic), chromatic.size(), R"(value="2")");
    auto scene = load_scene(dir.write("s.xml", xml));
    auto& moment = dynamic_cast<MomentIntegrator&>(const_cast<Integrator&>(scene->integrator()));
    PreprocessContext ctx;
    ctx.seed = 1;
    moment.preprocess(*scene, ctx);
    const auto& integrator = dynamic_cast<const GuidedVolPathIntegrator&>(moment.nested());
    const Medium* medium = nullptr;
    for (const auto& shape : scene->shapes())
        if (shape->interior_medium()) medium = shape->interior_medium();
    ASSERT_NE(medium, nullptr);
    WalkGuideSettings ws;
    ws.distance = DistanceGuiding::Vsp;
    ws.direction = DirectionGuiding::Product;
    const WalkGuide guide(*scene, integrator.field(), ws);
    const PhaseFunction& phase = medium->phase();
    int with_leaf = 0, guided = 0;
    for (int i = 0; i < 500; ++i) {
        Sampler s(4, 0, uint64_t(i));
        MediumInteraction mi;
        mi.p = Point3f(warp::square_to_uniform_sphere(s.next_2d()) * (0.9f * s.next_1d()));
        mi.wi = warp::square_to_uniform_sphere(s.next_2d());
        mi.medium = medium;
        mi.coeffs = medium->eval(mi.p);
        WalkGuideStats counts;
        GuidedVertex vertex(guide, counts);
        vertex.init(mi);
        ASSERT_EQ(counts.vertex_descents, 0u);  // init looks nothing up
        const int leaf = integrator.field().tree().leaf_at(mi.p);
        const float confidence = guide.trust().confidence(leaf, mi.coeffs.sigma_t);
        const bool trusted = leaf >= 0 && confidence >= kSkipConfidence;
        const float phase_prob = !trusted && leaf >= 0 ? 1.f : 1.f - 0.5f * confidence;
        const GuidedDirectionSampler ref(DirectionGuiding::Product, leaf >= 0 ? guide.prepared().direction_lobes(leaf) : LobeBlock(),
                                         phase, *guide.prepared().phase_lobes(phase), mi.wi, phase_prob);
        const Vec3f w = warp::square_to_uniform_sphere(s.next_2d());
        for (int again = 0; again < 2; ++again) {  // a second round asks the same object again
            vertex.prepare_direction();
            ASSERT_EQ(vertex.leaf(), leaf);
            ASSERT_EQ(vertex.guided(), ref.guided());
            ASSERT_EQ(vertex.direction_pdf(w), ref.pdf(w));
            ASSERT_EQ(vertex.estimate(ContinuationStage::Distance, w),
                      trusted ? guide.prepared().inscattered(leaf, phase, w) : Color3(0.f));
            ASSERT_EQ(vertex.estimate(ContinuationStage::Direction, w),
                      trusted ? guide.prepared().incident(leaf, phase, w) : Color3(0.f));
        }
        ASSERT_EQ(counts.vertices, 1u);
        ASSERT_EQ(counts.vertex_descents, 1u);  // the one descent (no hint: a fresh object)
        ASSERT_EQ(counts.vertex_mixtures, 1u);
        ASSERT_LE(counts.vertex_products, 1u);
        // The next segment's decision reads the same leaf, without another descent.
        DecisionRecord record;
        vertex.sample_distance(DistanceQuery{*medium, Ray(mi.p, w), 0.5f, Color3(1.f)}, kNoCameraBuffer, s, &record);
        ASSERT_EQ(record.leaf, leaf);
        ASSERT_EQ(counts.vertex_descents, 1u);
        with_leaf += leaf >= 0;
        guided += ref.guided();
    }
    EXPECT_GT(with_leaf, 400);
    EXPECT_GT(guided, 300);

    ws.distance_settings.c_T = 1.f;
    const WalkGuide unguided(*scene, integrator.field(), ws);
    WalkGuideStats counts;
    GuidedVertex vertex(unguided, counts);
    int scattered = 0;
    for (int i = 0; i < 2000; ++i) {
        Sampler s(9, 0, uint64_t(i));
        const Ray ray(Point3f(0.f), warp::square_to_uniform_sphere(s.next_2d()));
        MediumInteraction mi;
        mi.p = ray.o;
        mi.wi = -ray.d;
        mi.medium = medium;
        mi.coeffs = medium->eval(mi.p);
        vertex.init(mi);
        const FreeFlightSample f =
            vertex.sample_distance(DistanceQuery{*medium, ray, 0.999f, Color3(1.f)}, kNoCameraBuffer, s, nullptr);
        scattered += f.scattered;
        ASSERT_NEAR(f.weight.r, 1.f, 2e-4f) << "query " << i << (f.scattered ? " scattered" : " passed");
    }
    EXPECT_GT(scattered, 1000);
    EXPECT_GT(counts.vsp_queries, 1000u);
}

namespace {

std::string rrs_xml(const std::string& mode, float window = 1.f, int max_branches = 64) {
    return fmt::format(R"(<string name="rrs" value="{}"/><float name="rrs_window" value="{}"/>
        <integer name="rrs_max_branches" value="{}"/>)",
                       mode, window, max_branches);
}

struct RrsCase {
    const char* distance;
    const char* direction;
    const char* mode;
    float window;
};
const RrsCase kRrsCases[] = {{"incremental", "product", "grr", 1.f},
                             {"incremental", "product", "grrs", 1.f},
                             {"incremental", "product", "grrs", 5.f},
                             {"vsp", "product", "grrs", 5.f},
                             {"standard", "phase", "grrs", 1.f}};

std::string describe(const RrsCase& c) {
    return fmt::format("distance={} direction={} rrs={} s={}", c.distance, c.direction, c.mode, c.window);
}

}  // namespace

// 4096 spp: splitting's weights are heavy-tailed, and at 1024 spp the vectorised product's float stream
// (issue 49) put incremental+product+grr at 4.2 standard errors from 1 (1.0039 ± 0.00094) while seeds 23
// and 31 passed and 4096 and 8192 spp at seed 19 pass every case: half the standard error, a stricter test.
TEST(GuidedVolPathUnbiased, WhiteFurnaceWithRouletteSplitting) {
    TempDir dir("guided-furnace-rrs");
    const std::string grid = write_furnace_grid(dir);
    for (bool het : {false, true})
        for (const RrsCase& c : kRrsCases) {
            SCOPED_TRACE(fmt::format("{} {}", het ? "heterogeneous" : "homogeneous", describe(c)));
            Rendered r = render_scene_xml(
                guided_furnace_xml(het, grid,
                            guided(c.distance, c.direction, 100000, -1.f, "",
                                   rrs_xml(c.mode, c.window))),
                4096, 19, /*test_media=*/false);
            expect_constant_image(r, 1.0);
        }
}

TEST(GuidedVolPathUnbiased, PointLitFogWithRouletteSplittingMatchesVolpath) {
    TempDir dir("guided-lit-fog-rrs");
    const std::string grid = write_furnace_grid(dir);
    for (bool het : {false, true}) {
        Rendered ref =
            render_scene_xml(lit_fog_xml(het, grid, R"(<integrator type="volpath"/>)"), 1024, 7, false);
        for (const RrsCase& c : kRrsCases) {
            SCOPED_TRACE(fmt::format("{} {}", het ? "heterogeneous" : "homogeneous", describe(c)));
            Rendered g = render_scene_xml(
                lit_fog_xml(het, grid,
                            guided(c.distance, c.direction, 200000, -1.f, "",
                                   rrs_xml(c.mode, c.window))),
                1024, 8, false);
            expect_same_means(g, ref);
        }
    }
}

// The branch budget lowers q only: the image mean is volpath's.
TEST(GuidedVolPathUnbiased, BranchBudgetIsUnbiased) {
    TempDir dir("guided-rrs-budget");
    const std::string grid = write_furnace_grid(dir);
    Rendered ref = render_scene_xml(lit_fog_xml(false, grid, R"(<integrator type="volpath"/>)"), 1024, 7, false);
    Rendered g = render_scene_xml(
        lit_fog_xml(false, grid,
                    guided("incremental", "product", 200000, -1.f, "",
                           rrs_xml("grrs", 1.f) + R"(<float name="rrs_branch_budget" value="3"/>)")),
        1024, 9, false);
    expect_same_means(g, ref);
}

TEST(GuidedVolPathUnbiased, RouletteSplittingStatistics) {
    TempDir dir("guided-rrs-stats");
    const std::string grid = write_furnace_grid(dir);
    const auto s =
        guide_stats(lit_fog_xml(false, grid, guided("incremental", "product", 200000, -1.f, "", rrs_xml("grrs"))));
    ASSERT_TRUE(s.count("rrs_decisions"));
    EXPECT_GT(s.at("rrs_decisions"), 100.0);
    EXPECT_GT(s.at("rrs_kills"), 0.0);
    EXPECT_GT(s.at("rrs_splits"), 0.0);
    EXPECT_GT(s.at("rrs_extra_branches"), s.at("rrs_splits") - 0.5);
    EXPECT_GT(s.at("rrs_branches_per_camera_sample"), 1.0);
    // The cap (64) always holds; the 99.9th percentile is the benchmark's measure (576 camera
    // samples here: it would be the maximum).
    EXPECT_LE(s.at("rrs_branches_max"), 64.0);
    EXPECT_LT(s.at("rrs_branches_per_camera_sample"), 8.0);
    EXPECT_LT(s.at("rrs_invalid_estimate_fraction"), 0.5);  // most vertices are in valid fog leaves
    EXPECT_GT(s.at("rrs_pixel_estimate_seconds"), 0.0);
    // Guided RR alone never splits.
    const auto rr =
        guide_stats(lit_fog_xml(false, grid, guided("incremental", "product", 200000, -1.f, "", rrs_xml("grr"))));
    EXPECT_GT(rr.at("rrs_kills"), 0.0);
    EXPECT_EQ(rr.at("rrs_splits"), 0.0);
    EXPECT_EQ(rr.at("rrs_branches_max"), 1.0);
    // A cap of 2 branches per camera sample holds, by lowering q: the cap bounds the camera sample's
    // allowance (issue 55), so the allowance lowers q before the cap would (budget_limited, never
    // cap_limited).
    const auto cap = guide_stats(
        lit_fog_xml(false, grid, guided("incremental", "product", 200000, -1.f, "", rrs_xml("grrs", 1.f, 2))));
    EXPECT_LE(cap.at("rrs_branches_max"), 2.0);
    EXPECT_EQ(cap.at("rrs_branch_budget"), 2.0);
    EXPECT_GT(cap.at("rrs_budget_limited"), 0.0);
    EXPECT_EQ(cap.at("rrs_cap_limited"), 0.0);
    // The branch budget (issue 21): 3 branches per camera sample by construction, from a window that
    // splits freely; the cap (64) is not what limits it.
    const auto budget = guide_stats(lit_fog_xml(
        false, grid,
        guided("incremental", "product", 200000, -1.f, "",
               rrs_xml("grrs", 1.f) + R"(<float name="rrs_branch_budget" value="3"/>)")));
    EXPECT_LE(budget.at("rrs_branches_max"), 3.0);
    EXPECT_GT(budget.at("rrs_budget_limited"), 0.0);
    EXPECT_EQ(budget.at("rrs_cap_limited"), 0.0);
    EXPECT_GT(budget.at("rrs_splits"), 0.0);
    // rrs=standard reports no RR/splitting statistics.
    const auto none = guide_stats(lit_fog_xml(false, grid, guided("incremental", "product", 200000)));
    EXPECT_EQ(none.count("rrs_decisions"), 0u);
}

// Issue 59: the allocation learned while rendering changes every decision's share per cell, and the
// continuation's rule, between passes (its first passes explore with the configured mixtures, the
// coarse stage may train the full field or stop guiding). Each decision kind forced off (its unguided
// decision), forced on (allocation=false: the configured mixture everywhere) and allocated (the
// defaults) keeps volpath's image means, homogeneous and heterogeneous; and on this scene the
// allocation really mixes: of each sampling decision some cells are guided and some are not.
TEST(GuidedVolPathUnbiased, EveryDecisionOffOnAndAllocatedIsUnbiased) {
    TempDir dir("guided-allocation");
    const std::string grid = write_furnace_grid(dir);
    const std::string grrs = rrs_xml("grrs", 5.f);
    const std::string on = R"(<boolean name="allocation" value="false"/>)";
    const std::string allocated = R"(<boolean name="allocation" value="true"/>)";
    const std::string no_surface = allocated + R"(<boolean name="surface_guiding" value="false"/>)";
    const std::pair<const char*, std::string> cases[] = {
        {"every decision on", guided("incremental", "product", 200000, -1.f, on, grrs)},
        {"allocated", guided("incremental", "product", 200000, -1.f, allocated, grrs)},
        {"distance off", guided("standard", "product", 200000, -1.f, allocated, grrs)},
        {"direction off", guided("incremental", "phase", 200000, -1.f, allocated, grrs)},
        {"surface off", guided("incremental", "product", 200000, -1.f, no_surface, grrs)},
        {"continuation off", guided("incremental", "product", 200000, -1.f, allocated)},
    };
    uint64_t seed = 20;
    for (const auto& [name, integrator] : cases) {
        SCOPED_TRACE(name);
        expect_lit_fog_means_of_volpath(grid, integrator, seed++);
    }
    // At 16 spp the full stage has not yet been confirmed against its control samples (4 + 16 spp).
    const auto s = guide_stats(lit_fog_xml(false, grid, guided("incremental", "product", 200000, -1.f, allocated, grrs)), 16);
    EXPECT_EQ(s.at("training_stage"), 1.0);  // the full field: the coarse stage's prediction said it pays
    for (const char* kind : {"distance", "direction"}) {
        const double guided_fraction = s.at(fmt::format("allocation_{}_guided_fraction", kind));
        EXPECT_GT(guided_fraction, 0.0) << kind;
        EXPECT_LT(guided_fraction, 1.0) << kind;
    }
}

// Issue 39: refinement during the render (refine_passes): further photon passes, added to the field
// between passes at doublings of spp (from 16 spp: 16, 32, ... while the last one paid), change the
// guide; every pass samples one fixed field, so the image is still volpath's in expectation.
TEST(GuidedVolPathUnbiased, RefinementDuringTheRenderIsUnbiased) {
    TempDir dir("guided-refine");
    const std::string grid = write_furnace_grid(dir);
    const std::string refine = R"(<integer name="refine_passes" value="3"/>)";
    expect_lit_fog_means_of_volpath(grid, guided("incremental", "product", 200000, -1.f, refine, rrs_xml("grrs", 5.f)), 8);
    const auto s = guide_stats(lit_fog_xml(false, grid, guided("incremental", "product", 200000, -1.f, refine)), 64);
    EXPECT_GE(s.at("refine_passes"), 1.0);
    EXPECT_GT(s.at("refine_deposits"), 0.0);
    EXPECT_GT(s.at("field_memory_bytes"), 0.0);
    EXPECT_GT(s.at("refine_stretch1_inefficiency"), 0.0);
}

// Issue 37 deliverable 2: a render's medium vertices (GuidedVertex, one object per vertex begun before
// the distance-stage continuation) make at most one leaf descent and build at most one direction
// mixture each, and the vertices the distance-stage continuation ends (roulette) build none: mixtures
// <= vertices - kills. An object that built its mixture at init, as the walk's direction decision did
// before the object was begun ahead of the continuation, fails the last check (every vertex a mixture).
// With ears (its own statistics, no estimate-driven kills) the descents per vertex are bounded too.
TEST(GuidedVolPathUnbiased, GuidedVertexLooksUpOnceAndBuildsNothingForKilledPaths) {
    TempDir dir("guided-vertex-counts");
    const std::string grid = write_furnace_grid(dir);
    for (const char* distance : {"vsp", "incremental"}) {
        SCOPED_TRACE(distance);
        // 8 spp: the bounded splitting (issue 55) makes fewer branches than the unbounded window did at 4.
        const auto s = guide_stats(lit_fog_xml(false, grid, guided(distance, "product", 200000, -1.f, "",
                                                                   rrs_xml("grrs"))),
                                   8);
        ASSERT_TRUE(s.count("guided_vertices"));
        EXPECT_GT(s.at("guided_vertices"), 1000.0);
        // vsp descends once per vertex it does not inherit; the incremental bins walk the segment
        // through the tree and hand the vertex its leaf (issue 49): no descent at all.
        if (std::string(distance) == "vsp") {
            EXPECT_GT(s.at("guided_vertex_descents"), 0.0);
            EXPECT_LE(s.at("guided_vertex_descents"), 1.0);  // per vertex
        } else {
            EXPECT_LT(s.at("guided_vertex_descents"), 0.01);
        }
        EXPECT_GT(s.at("guided_vertex_distance_kills"), 0.01);
        EXPECT_GT(s.at("guided_vertex_mixtures"), 0.1);
        EXPECT_LE(s.at("guided_vertex_mixtures") + s.at("guided_vertex_distance_kills"), 1.0);
        EXPECT_LE(s.at("guided_vertex_products"), s.at("guided_vertex_mixtures"));
        EXPECT_GT(s.at("guided_vertex_products"), 0.0);
    }
    const auto ears = guide_stats(lit_fog_xml(false, grid, guided("incremental", "product", 200000, -1.f, "",
                                                                  R"(<string name="rrs" value="ears"/>)")));
    EXPECT_GT(ears.at("guided_vertices"), 500.0);
    EXPECT_LE(ears.at("guided_vertex_descents"), 1.0);
    EXPECT_LE(ears.at("guided_vertex_mixtures") + ears.at("guided_vertex_distance_kills"), 1.0);
    // Directions not guided: no mixture is built at all.
    const auto phase =
        guide_stats(lit_fog_xml(false, grid, guided("vsp", "phase", 200000, -1.f, "", rrs_xml("grrs"))), 8);
    EXPECT_GT(phase.at("guided_vertices"), 1000.0);
    EXPECT_EQ(phase.at("guided_vertex_mixtures"), 0.0);
    EXPECT_LE(phase.at("guided_vertex_descents"), 1.0);
}

// Issue 37: distance="vsp" (one decision per segment, docs/theory.md §7.10): the white furnace stays 1
// (homogeneous: the closed-form decision; heterogeneous: the resampled tentative collisions), the
// point-lit fog's image means match volpath's (homogeneous and heterogeneous), and the statistics
// show the segment decision was made from the field (vsp queries, few unguided ones, the
// heterogeneous ones resampled).
TEST(GuidedVolPathUnbiased, VspDistanceIsUnbiased) {
    TempDir dir("guided-vsp");
    const std::string grid = write_furnace_grid(dir);
    for (bool het : {false, true}) {
        SCOPED_TRACE(het ? "heterogeneous" : "homogeneous");
        Rendered r = render_scene_xml(guided_furnace_xml(het, grid, guided("vsp", "product", 100000)), 1024, 21, false);
        expect_constant_image(r, 1.0);
        Rendered ref = render_scene_xml(lit_fog_xml(het, grid, R"(<integrator type="volpath"/>)"), 1024, 5, false);
        Rendered g = render_scene_xml(lit_fog_xml(het, grid, guided("vsp", "product", 200000)), 1024, 8, false);
        expect_same_means(g, ref);
    }
    const auto s = guide_stats(lit_fog_xml(false, grid, guided("vsp", "product", 200000)));
    EXPECT_GT(s.at("distance_vsp_queries"), 100.0);
    EXPECT_LT(s.at("distance_vsp_unguided_fraction"), 0.5);
    EXPECT_GT(s.at("distance_vsp_scattered_fraction"), 0.05);
    EXPECT_LT(s.at("distance_vsp_scattered_fraction"), 0.95);
    EXPECT_EQ(s.at("distance_vsp_resampled_fraction"), 0.0);
    const auto h = guide_stats(lit_fog_xml(true, grid, guided("vsp", "product", 200000)));
    EXPECT_GT(h.at("distance_vsp_queries"), 100.0);
    EXPECT_GT(h.at("distance_vsp_resampled_fraction"), 0.5);
    EXPECT_GT(h.at("distance_vsp_scattered_fraction"), 0.05);
}

// Issue 37, deliverable 5: distance="vsp" with its equiangular share (docs/theory.md §7.10.1; 0.5)
// toward the point light: the point-lit fog's image means match volpath's, and the statistics show the
// equiangular mixture drew the scatter distances. The heterogeneous (chromatic) fog keeps the
// resampled decision without it (homogeneous only) and stays unbiased.
TEST(GuidedVolPathUnbiased, VspEquiangularIsUnbiased) {
    TempDir dir("guided-vsp-equi");
    const std::string grid = write_furnace_grid(dir);
    for (bool het : {false, true}) {
        SCOPED_TRACE(het ? "heterogeneous" : "homogeneous");
        Rendered ref = render_scene_xml(lit_fog_xml(het, grid, R"(<integrator type="volpath"/>)"), 1024, 5, false);
        Rendered g = render_scene_xml(lit_fog_xml(het, grid, guided("vsp", "product", 200000)), 1024, 8, false);
        expect_same_means(g, ref);
        const auto s = guide_stats(lit_fog_xml(het, grid, guided("vsp", "product", 200000)));
        if (het) {
            EXPECT_EQ(s.at("distance_vsp_equiangular_fraction"), 0.0);
        } else {
            EXPECT_GT(s.at("distance_vsp_equiangular_fraction"), 0.9);  // scatters drawn from the mixture
        }
    }
}

// A chromatic heterogeneous medium three times denser than the lit fog's (optical depths of several
// mean free paths per channel, channel 1 half the others): distance="vsp" (the resampled decision,
// per-channel weights) against volpath.
TEST(GuidedVolPathUnbiased, VspDenseChromaticHeterogeneousMatchesVolpath) {
    TempDir dir("guided-vsp-dense");
    const std::string grid = write_furnace_grid(dir);
    auto dense = [&](const std::string& integrator) {
        std::string xml = lit_fog_xml(true, grid, integrator);
        const std::string scale = R"(<float name="scale" value="0.3"/>)";
        EXPECT_NE(xml.find(scale), std::string::npos);
        return xml.replace(xml.find(scale), scale.size(), R"(<float name="scale" value="1"/>)");
    };
    Rendered ref = render_scene_xml(dense(R"(<integrator type="volpath"/>)"), 1024, 5, false);
    Rendered g = render_scene_xml(dense(guided("vsp", "product", 200000)), 1024, 8, false);
    expect_same_means(g, ref);
    const auto s = guide_stats(dense(guided("vsp", "product", 200000)));
    EXPECT_GT(s.at("distance_vsp_resampled_fraction"), 0.5);
}

// Issue 37, deliverable 3: camera segments take P_G from the raymarched pixel estimate's per-pixel
// buffer (docs/theory.md §7.10.2; on by default with distance="vsp", so VspDistanceIsUnbiased runs with
// it): the buffer exists, holds probabilities, and is read by the camera segments' decisions (the
// fraction of vsp queries made from it). The point-lit fog stays unbiased with the buffer in the
// heterogeneous medium too.
TEST(GuidedVolPathUnbiased, VspCameraBufferIsUsedAndUnbiased) {
    TempDir dir("guided-vsp-camera");
    const std::string grid = write_furnace_grid(dir);
    {
        auto scene = load_scene(dir.write("s.xml", lit_fog_xml(false, grid, guided("vsp", "product", 200000))));
        RenderOptions ro;
        ro.spp = 1;
        render(*scene, ro);
        const auto& moment = dynamic_cast<const MomentIntegrator&>(scene->integrator());
        const auto& g = dynamic_cast<const GuidedVolPathIntegrator&>(moment.nested());
        int valid = 0;
        for (int y = 0; y < 12; ++y)
            for (int x = 0; x < 12; ++x) {
                const float p = g.pixel_estimate().camera_scatter_probability(Point2f((x + 0.5f) / 12.f, (y + 0.5f) / 12.f));
                if (std::isnan(p)) continue;
                ++valid;
                EXPECT_GE(p, 0.f);
                EXPECT_LE(p, 1.f);
            }
        EXPECT_GT(valid, 72);  // the fog box fills most of the view
    }
    const auto on = guide_stats(lit_fog_xml(false, grid, guided("vsp", "product", 200000)));
    EXPECT_GT(on.at("distance_vsp_camera_fraction"), 0.0);
    Rendered ref = render_scene_xml(lit_fog_xml(true, grid, R"(<integrator type="volpath"/>)"), 1024, 5, false);
    Rendered g = render_scene_xml(lit_fog_xml(true, grid, guided("vsp", "product", 200000)), 1024, 9, false);
    expect_same_means(g, ref);
}
