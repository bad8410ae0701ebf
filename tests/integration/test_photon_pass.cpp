// The photon pre-pass and the guiding field it trains (issue 6, docs/theory.md §5.2, §14.12):
//  - direction convention: photons from a point light deposit directions towards the light, so the
//    fitted leaf mixtures point at it;
//  - fluence: in a purely absorbing medium around a point light of intensity I the fluence is
//    exactly I e^(-sigma r) / r^2; every leaf with >= 1000 samples matches its box average within 10 %
//    (leaves of 2000-4000 samples) and the mean ratio over leaves is 1 within 1 %;
//  - determinism: the same seed gives a bit-identical field for 1 and 2 threads;
//  - guided_volpath: trains, saves and reloads the field through the CLI, and renders volpath's image;
//    `volguide info --field` summarises a saved field.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "support/cli.h"
#include "support/volpath_test_util.h"
#include "volguide/core/sampler.h"
#include "volguide/guiding/field_io.h"
#include "volguide/integrators/guided/guided_volpath.h"
#include "volguide/integrators/guided/training/medium_occupancy.h"
#include "volguide/integrators/guided/training/photon_pass.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

using namespace volguide;
using namespace volguide::test;

namespace {

std::string point_light_scene(const Point3f& light, float sigma_t, float albedo, const std::string& integrator) {
    return fmt::format(R"(<scene version="3.0.0">
    <integrator type="moment">{4}</integrator>
    <medium type="homogeneous" id="fog">
        <float name="sigma_t" value="{3}"/><float name="albedo" value="{5}"/>
        <phase type="isotropic"/>
    </medium>
    <shape type="sphere"><float name="radius" value="2"/><bsdf type="null"/><ref name="interior" id="fog"/></shape>
    <emitter type="point">
        <point name="position" value="{0}, {1}, {2}"/><rgb name="intensity" value="10"/>
        <ref name="medium" id="fog"/>
    </emitter>
    <sensor type="perspective">
        <ref name="medium" id="fog"/>
        <transform name="to_world"><lookat origin="0, 0, 1.5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
            <rfilter type="box"/></film>
    </sensor>
</scene>)",
                       light.x, light.y, light.z, sigma_t, integrator, albedo);
}

std::unique_ptr<Scene> load_photon_scene(const TempDir& dir, const std::string& xml) {
    return load_scene(dir.write("scene.xml", xml));
}

// A photon pass with uniform (unfocused) emission, and the share of its photons that deposited.
PhotonPassResult trace_unfocused(const Scene& scene, int64_t photons, uint64_t seed) {
    PhotonPassSettings ps;
    ps.photons = photons;
    ps.focus = false;
    PreprocessContext ctx;
    ctx.seed = seed;
    return trace_photons(scene, ps, ctx);
}
double depositing_rate(const PhotonPassResult& r) {
    return double(r.photons_depositing) / double(r.photons_traced);
}

GuidingField train_photons(const Scene& scene, int64_t photons, uint64_t seed, int max_samples) {
    PhotonPassSettings ps;
    ps.photons = photons;
    PreprocessContext ctx;
    ctx.seed = seed;
    PhotonPassResult r = trace_photons(scene, ps, ctx);
    EXPECT_EQ(r.photons_traced, photons);
    GuidingFieldSettings fs;
    fs.tree.max_samples = max_samples;
    fs.lobes = 4;
    return GuidingField::build(guiding_bounds(scene), r.samples, fs);
}

}  // namespace

TEST(PhotonPass, LeafMixturesPointTowardsThePointLight) {
    TempDir dir("photons-direction");
    const Point3f light(1.5f, 0.f, 0.f);
    auto scene = load_photon_scene(dir, point_light_scene(light, 0.3f, 0.5f, R"(<integrator type="volpath"/>)"));
    GuidingField field = train_photons(*scene, 400000, 1, 2000);
    int checked = 0;
    for (int l = 0; l < field.tree().leaf_count(); ++l) {
        const GuidingLeaf& leaf = field.leaves()[size_t(l)];
        const Point3f c = field.tree().leaf_bounds(l).center();
        const Vec3f to_light = light - c;
        // Leaves well away from the light (on the -x side), where it subtends a small angle.
        if (!leaf.valid || leaf.samples < 1000 || c.x > 0.f || norm(c) > 1.8f) continue;
        ++checked;
        EXPECT_GT(dot(normalize(leaf.vmm.mean_vector()), normalize(to_light)), 0.9f)
            << "leaf " << l << " at (" << c.x << ", " << c.y << ", " << c.z << ")";
    }
    EXPECT_GE(checked, 4);
}

TEST(PhotonPass, FluenceOfAnAbsorbingMediumAroundAPointLight) {
    TempDir dir("photons-fluence");
    const float sigma = 0.5f, intensity = 10.f;
    auto scene = load_photon_scene(dir, point_light_scene(Point3f(0.f), sigma, 0.f, R"(<integrator type="volpath"/>)"));
    // Leaves of 2000-4000 samples: a per-leaf standard error of 1.6-2.2 %, so 10 % is > 4.5 sigma.
    GuidingField field = train_photons(*scene, 2000000, 2, 4000);
    int checked = 0;
    double ratio_sum = 0;
    for (int l = 0; l < field.tree().leaf_count(); ++l) {
        const GuidingLeaf& leaf = field.leaves()[size_t(l)];
        const BBox3f box = field.tree().leaf_bounds(l);
        bool inside = true;  // the whole box inside the medium sphere, and away from the light
        for (int k = 0; k < 8; ++k) {
            const Point3f corner((k & 1) ? box.hi.x : box.lo.x, (k & 2) ? box.hi.y : box.lo.y,
                                 (k & 4) ? box.hi.z : box.lo.z);
            inside &= norm(corner) < 1.99f;
        }
        const Vec3f e = box.extents();
        if (!inside || leaf.samples < 1000 || box.contains(Point3f(0.f)) || norm(box.center()) < 0.6f) continue;
        // The box average of I e^(-sigma r) / r^2 by stratified quadrature.
        double sum = 0;
        const int n = 24;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                for (int k = 0; k < n; ++k) {
                    const Point3f p = box.lo + Vec3f(e.x * (i + 0.5f) / n, e.y * (j + 0.5f) / n, e.z * (k + 0.5f) / n);
                    const double r = norm(p);
                    sum += intensity * std::exp(-sigma * r) / (r * r);
                }
        const double expected = sum / (n * n * n);
        ++checked;
        EXPECT_NEAR(leaf.fluence.r, expected, 0.1 * expected) << "leaf " << l << " with " << leaf.samples << " samples";
        ratio_sum += leaf.fluence.r / expected;
    }
    EXPECT_GE(checked, 10);
    // No systematic bias: the mean ratio over the leaves within 1 % (its standard error is ~0.2 %).
    EXPECT_NEAR(ratio_sum / checked, 1.0, 0.01);
}

TEST(PhotonPass, FieldIsIdenticalForOneAndTwoThreads) {
    TempDir dir("photons-determinism");
    auto scene = load_photon_scene(dir, point_light_scene(Point3f(0.5f, 0.f, 0.f), 0.8f, 0.9f, R"(<integrator type="volpath"/>)"));
    std::string a, b;
    tbb::task_arena(1).execute([&] { a = serialize_field(train_photons(*scene, 100000, 3, 500)); });
    tbb::task_arena(2).execute([&] { b = serialize_field(train_photons(*scene, 100000, 3, 500)); });
    EXPECT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << "the trained field depends on the thread count";
    std::string c;
    tbb::task_arena(2).execute([&] { c = serialize_field(train_photons(*scene, 100000, 4, 500)); });
    EXPECT_FALSE(a == c) << "another seed must give another field";
}

// The deposit cap stops tracing after the wave that reaches it, the same photons for any thread
// count; without the cap every photon is traced.
TEST(PhotonPass, DepositCapStopsAtTheSameWaveForAnyThreadCount) {
    TempDir dir("photons-cap");
    auto scene = load_photon_scene(dir, point_light_scene(Point3f(0.5f, 0.f, 0.f), 2.f, 0.95f, R"(<integrator type="volpath"/>)"));
    PhotonPassSettings ps;
    ps.photons = 400000;
    PreprocessContext ctx;
    ctx.seed = 5;
    PhotonPassResult full;
    tbb::task_arena(2).execute([&] { full = trace_photons(*scene, ps, ctx); });
    EXPECT_EQ(full.photons_traced, ps.photons);
    EXPECT_FALSE(full.deposit_limited);
    ps.max_deposits = int64_t(full.samples.size()) / 4;
    PhotonPassResult one, two;
    tbb::task_arena(1).execute([&] { one = trace_photons(*scene, ps, ctx); });
    tbb::task_arena(2).execute([&] { two = trace_photons(*scene, ps, ctx); });
    EXPECT_TRUE(one.deposit_limited);
    EXPECT_LT(one.photons_traced, ps.photons / 2);
    EXPECT_GE(int64_t(one.samples.size()), ps.max_deposits);  // whole waves: at or just past the cap
    EXPECT_LT(int64_t(one.samples.size()), 2 * ps.max_deposits);
    EXPECT_EQ(one.photons_traced, two.photons_traced);
    ASSERT_EQ(one.samples.size(), two.samples.size());
    for (size_t i = 0; i < one.samples.size(); ++i) {
        ASSERT_EQ(one.samples[i].position, two.samples[i].position) << i;
        ASSERT_EQ(one.samples[i].weight, two.samples[i].weight) << i;
    }
}

// Photons from an area light leave its surface: they used to start exactly on it and hit the light
// itself at t ~ 0, so no photon from an area light ever reached a medium (`thin`, `sss`, `backlit`
// and `fogbox` trained empty or nearly empty fields). A 0.3 m square facing a fog sphere of radius
// 1 at distance 2.5: a cosine-weighted ray hits the sphere with probability (R/d)^2 = 0.16 and then
// collides with probability ~0.70 (sigma R = 1, impact parameter ~uniform): ~11 % deposit.
TEST(PhotonPass, AreaLightPhotonsReachTheMedium) {
    TempDir dir("photons-area");
    auto scene = load_photon_scene(dir, R"(<scene version="3.0.0">
    <integrator type="volpath"/>
    <medium type="homogeneous" id="fog">
        <float name="sigma_t" value="1"/><float name="albedo" value="0"/><phase type="isotropic"/>
    </medium>
    <shape type="sphere"><bsdf type="null"/><ref name="interior" id="fog"/></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.15"/><rotate y="1" angle="-90"/><translate x="2.5"/></transform>
        <emitter type="area"><rgb name="radiance" value="10"/></emitter>
    </shape>
    <sensor type="perspective">
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
    </sensor>
</scene>)");
    EXPECT_NEAR(depositing_rate(trace_unfocused(*scene, 200000, 9)), 0.1125, 0.02);
}

// A lamp inside fog whose shape (or, for a point light, whose emitter) names no medium: the camera's
// walk never needs it, but photons must start in the fog that encloses it. Purely absorbing fog of
// radius 2 around a lamp at the centre: a photon collides before leaving with probability
// 1 - exp(-sigma (2 - r_lamp)) (the fog bounds are a null sphere). Started in vacuum, as they were
// before, none did (fogbox's field missed its lamp's direct light).
TEST(PhotonPass, PhotonsOfALampThatNamesNoMediumStartInTheFogAroundIt) {
    const float sigma = 0.5f;
    for (bool point : {false, true}) {
        SCOPED_TRACE(point ? "point light without a medium" : "sphere light without media");
        TempDir dir("photons-lamp-in-fog");
        const std::string lamp =
            point ? R"(<emitter type="point"><point name="position" value="0, 0, 0"/><rgb name="intensity" value="10"/></emitter>)"
                  : R"(<shape type="sphere"><float name="radius" value="0.05"/>
                       <emitter type="area"><rgb name="radiance" value="10"/></emitter></shape>)";
        auto scene = load_photon_scene(dir, fmt::format(R"(<scene version="3.0.0">
    <integrator type="volpath"/>
    <medium type="homogeneous" id="fog">
        <float name="sigma_t" value="{0}"/><float name="albedo" value="0"/><phase type="isotropic"/>
    </medium>
    <shape type="sphere"><float name="radius" value="2"/><bsdf type="null"/><ref name="interior" id="fog"/></shape>
    {1}
    <sensor type="perspective">
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
    </sensor>
</scene>)",
                                           sigma, lamp));
        const PhotonPassResult r = trace_unfocused(*scene, 100000, 11);
        const double expected = 1.0 - std::exp(-sigma * (2.0 - (point ? 0.0 : 0.05)));
        EXPECT_NEAR(depositing_rate(r), expected, 0.01);  // binomial standard error 0.0015
        size_t direct = 0;
        for (const RadianceSample& d : r.samples) direct += d.direct;
        EXPECT_EQ(direct, r.samples.size());  // albedo 0: every collision is the lamp's direct light
    }
}

// medium_enclosing (photons' start medium) and medium_along (the leaves' medium fractions): inside a
// fog sphere the fog; outside it, where probes escape, no medium even though the camera sits in that
// fog (the fog is bounded); with fog that no shape bounds (the sensor's own medium) the fog everywhere.
TEST(MediumOccupancy, EnclosingMediumInsideOutsideAndUnbounded) {
    const std::string fog = R"(<medium type="homogeneous" id="fog"><float name="sigma_t" value="1"/></medium>)";
    const std::string sensor = R"(<sensor type="perspective"><ref name="medium" id="fog"/>
        <transform name="to_world"><lookat origin="0, 0, 1" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>)";
    TempDir dir("enclosing-medium");
    auto bounded = load_photon_scene(dir, R"(<scene version="3.0.0">)" + fog +
                                 R"(<shape type="sphere"><float name="radius" value="2"/><bsdf type="null"/>
                                    <ref name="interior" id="fog"/></shape>)" +
                                 sensor + "</scene>");
    const Medium* in_fog = bounded->sensor().medium();
    ASSERT_NE(in_fog, nullptr);
    const Medium* ambient = ambient_medium(*bounded);
    EXPECT_EQ(ambient, nullptr);
    EXPECT_EQ(medium_enclosing(*bounded, Point3f(0.3f, -0.2f, 0.1f), ambient), in_fog);
    EXPECT_EQ(medium_enclosing(*bounded, Point3f(3.f, 3.f, 3.f), ambient), nullptr);  // every probe escapes
    EXPECT_EQ(medium_enclosing(*bounded, Point3f(3.f, 0.f, 0.f), ambient), nullptr);  // a probe meets the sphere
    // medium_along: an escaping probe gets the ambient medium (none: the fog is bounded), a probe
    // that meets the sphere from outside its exterior (none), from inside its interior.
    EXPECT_EQ(medium_along(*bounded, Ray(Point3f(3.f, 3.f, 3.f), Vec3f(1.f, 0.f, 0.f)), ambient), nullptr);
    EXPECT_EQ(medium_along(*bounded, Ray(Point3f(3.f, 0.f, 0.f), Vec3f(-1.f, 0.f, 0.f)), ambient), nullptr);
    EXPECT_EQ(medium_along(*bounded, Ray(Point3f(0.f, 0.f, 0.f), Vec3f(1.f, 0.f, 0.f)), ambient), in_fog);
    // The medium fractions of leaves (one-leaf trees): outside the bounded fog none, although the
    // camera sits in it and most probes from there escape; inside it all.
    EXPECT_EQ(medium_fractions(*bounded, SpatialTree(BBox3f(Point3f(2.5f), Point3f(3.5f))), 64, 1),
              std::vector<float>{0.f});
    EXPECT_EQ(medium_fractions(*bounded, SpatialTree(BBox3f(Point3f(-0.5f), Point3f(0.5f))), 64, 1),
              std::vector<float>{1.f});
    auto unbounded = load_photon_scene(dir, R"(<scene version="3.0.0">)" + fog +
                                   R"(<shape type="rectangle"><bsdf type="diffuse"/></shape>)" + sensor + "</scene>");
    EXPECT_EQ(ambient_medium(*unbounded), unbounded->sensor().medium());
    EXPECT_EQ(medium_enclosing(*unbounded, Point3f(3.f, 3.f, 3.f), ambient_medium(*unbounded)),
              unbounded->sensor().medium());
    EXPECT_EQ(medium_fractions(*unbounded, SpatialTree(BBox3f(Point3f(2.5f), Point3f(3.5f))), 64, 1),
              std::vector<float>{1.f});
}

// A sun over a small absorbing fog box on a large ground: the bounding sphere's disk is ~600 times
// the box's cross-section, so unfocused emission wastes > 99 % of the photons. Focused emission
// (emission_focus.h) must deposit far more of them, and its compensated flux must still give the
// analytic fluence E exp(-sigma depth) in every leaf inside the box.
TEST(PhotonPass, FocusedEmissionFindsASmallMediumAndStaysUnbiased) {
    TempDir dir("photons-focus");
    const float sigma = 1.f, irradiance = 2.f;
    auto scene = load_photon_scene(dir, fmt::format(R"(<scene version="3.0.0">
    <integrator type="volpath"/>
    <medium type="homogeneous" id="fog">
        <float name="sigma_t" value="{0}"/><float name="albedo" value="0"/><phase type="isotropic"/>
    </medium>
    <shape type="cube"><transform name="to_world"><scale value="0.5"/></transform>
        <bsdf type="null"/><ref name="interior" id="fog"/></shape>
    <shape type="rectangle"><transform name="to_world"><scale value="10"/><rotate x="1" angle="-90"/>
        <translate y="-1"/></transform><bsdf type="diffuse"/></shape>
    <emitter type="directional"><vector name="direction" value="0, -1, 0"/>
        <rgb name="irradiance" value="{1}"/></emitter>
    <sensor type="perspective">
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
    </sensor>
</scene>)", sigma, irradiance));
    PhotonPassSettings ps;
    ps.photons = 400000;
    ps.max_depth = 1;
    PreprocessContext ctx;
    ctx.seed = 8;
    ps.focus = false;
    const PhotonPassResult plain = trace_photons(*scene, ps, ctx);
    ps.focus = true;
    const PhotonPassResult focused = trace_photons(*scene, ps, ctx);
    EXPECT_EQ(plain.pilot_photons, 0);
    EXPECT_EQ(focused.pilot_photons, ps.photons / 8 + 1);
    const double plain_rate = double(plain.photons_depositing) / double(plain.photons_traced);
    const double focused_rate = double(focused.photons_depositing) / double(focused.photons_traced);
    EXPECT_LT(plain_rate, 0.003);
    EXPECT_GT(focused_rate, 30.0 * plain_rate) << "plain " << plain_rate << " focused " << focused_rate;

    GuidingFieldSettings fs;
    fs.tree.max_samples = 4000;
    fs.lobes = 4;
    const GuidingField field = GuidingField::build(guiding_bounds(*scene), focused.samples, fs);
    int checked = 0;
    double ratio_sum = 0;
    for (int l = 0; l < field.tree().leaf_count(); ++l) {
        const GuidingLeaf& leaf = field.leaves()[size_t(l)];
        const BBox3f box = field.tree().leaf_bounds(l);
        if (leaf.samples < 1000) continue;
        // The fluence estimate is per leaf volume: the integral of E exp(-sigma (0.5 - y)) over
        // the leaf's part of the fog box, divided by the leaf's volume.
        auto overlap = [](float lo, float hi) { return std::max(0.f, std::min(hi, 0.5f) - std::max(lo, -0.5f)); };
        const double y0 = std::max(box.lo.y, -0.5f), y1 = std::min(box.hi.y, 0.5f);
        if (!(y1 > y0)) continue;
        const double integral = irradiance * overlap(box.lo.x, box.hi.x) * overlap(box.lo.z, box.hi.z) *
                                (std::exp(-sigma * (0.5 - y1)) - std::exp(-sigma * (0.5 - y0))) / sigma;
        const Vec3f e = box.extents();
        const double expected = integral / (double(e.x) * e.y * e.z);
        ++checked;
        EXPECT_NEAR(leaf.fluence.r, expected, 0.1 * expected) << "leaf " << l << " with " << leaf.samples << " samples";
        ratio_sum += leaf.fluence.r / expected;
    }
    EXPECT_GE(checked, 8);
    EXPECT_NEAR(ratio_sum / std::max(checked, 1), 1.0, 0.02);
}

TEST(GuidedVolPath, TrainsSavesLoadsAndRendersWhatVolpathRenders) {
    TempDir dir("guided-volpath");
    const std::string field_path = dir.file("field.vgf");
    const Point3f light(0.7f, 0.3f, 0.f);
    const std::string guided =
        fmt::format(R"(<integrator type="guided_volpath"><integer name="photons" value="50000"/>
            <string name="distance" value="standard"/><string name="direction" value="phase"/>
            <string name="rrs" value="standard"/><string name="save_field" value="{}"/></integrator>)",
                    field_path);
    Rendered g = render_scene_xml(point_light_scene(light, 0.8f, 0.9f, guided), 64, 5, false);
    ASSERT_TRUE(std::filesystem::exists(field_path));
    const GuidingField saved = load_field(field_path);
    EXPECT_GT(saved.tree().leaf_count(), 1);
    // Same seed, same walk: exactly volpath's image.
    Rendered v = render_scene_xml(point_light_scene(light, 0.8f, 0.9f, R"(<integrator type="volpath"/>)"), 64, 5, false);
    EXPECT_TRUE(g.mean.pixels == v.mean.pixels);
    // Loading the saved field through the CLI; a corrupt one is an input error naming the file.
    const std::string load_xml = point_light_scene(
        light, 0.8f, 0.9f,
        fmt::format(R"(<integrator type="guided_volpath"><string name="distance" value="standard"/>
            <string name="direction" value="phase"/><string name="rrs" value="standard"/>
            <string name="load_field" value="{}"/></integrator>)",
                    field_path));
    CliResult ok = run_cli({"render", dir.write("load.xml", load_xml), "-o", dir.file("l.exr"), "--spp", "4", "--quiet"});
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    CliResult info = run_cli({"info", "--field", field_path});
    EXPECT_EQ(info.exit_code, 0) << info.err;
    EXPECT_NE(info.out.find(fmt::format("leaves: {} (", saved.tree().leaf_count())), std::string::npos) << info.out;
    EXPECT_EQ(run_cli({"info", "--field", field_path, dir.file("load.xml")}).exit_code, 2);  // one or the other
    {
        std::ofstream(field_path, std::ios::binary | std::ios::trunc) << "garbage";
    }
    CliResult bad_info = run_cli({"info", "--field", field_path});
    EXPECT_EQ(bad_info.exit_code, 1);
    EXPECT_NE(bad_info.err.find("field.vgf"), std::string::npos) << bad_info.err;
    CliResult bad = run_cli({"render", dir.file("load.xml"), "-o", dir.file("b.exr"), "--spp", "4", "--quiet"});
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_NE(bad.err.find("field.vgf"), std::string::npos) << bad.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("b.exr")));
}

TEST(GuidedVolPath, BadRouletteSplittingParametersAreErrorsNamingTheLine) {
    TempDir dir("guided-volpath-errors");
    auto run = [&](const std::string& params) {
        const std::string xml =
            point_light_scene(Point3f(0.f), 0.5f, 0.5f, R"(<integrator type="guided_volpath">)" + params + "</integrator>");
        return run_cli({"render", dir.write("s.xml", xml), "-o", dir.file("o.exr"), "--spp", "1", "--quiet"});
    };
    struct Case {
        std::string params, message;
    };
    for (const Case& c : std::vector<Case>{
             {R"(<float name="rrs_window" value="0.5"/>)", "rrs_window must be"},
             {R"(<float name="rrs_q_min" value="0"/>)", "rrs_q_min must be"},
             {R"(<float name="rrs_q_max" value="0.5"/>)", "rrs_q_max must be"},
             {R"(<integer name="rrs_max_branches" value="0"/>)", "rrs_max_branches must be"},
             {R"(<float name="rrs_branch_budget" value="0.5"/>)", "rrs_branch_budget must be"},
             {R"(<string name="rrs" value="standard"/><float name="rrs_window" value="5"/>)",
              "only applies to rrs=grr, grrs or ears"},
             {R"(<string name="rrs" value="standard"/><boolean name="allocation" value="false"/>)"
              R"(<integer name="pixel_estimate_rays" value="8"/>)",
              "pixel_estimate_rays only applies"},
             {R"(<integer name="selection_spp" value="0"/>)", "'selection_spp' was retired"},
             {R"(<integer name="selection_min_samples" value="8"/>)", "'selection_min_samples' was retired"},
             {R"(<integer name="ears_min_samples" value="8"/>)", "ears_min_samples only applies to rrs=ears"},
             {R"(<string name="distance" value="vsp_product"/>)", "distance=\"vsp_product\" was retired"},
             {R"(<string name="distance" value="tabulated"/>)", "distance=\"tabulated\" was retired"},
             {R"(<string name="distance" value="bins"/>)", "invalid distance 'bins' (one of: standard, incremental, vsp)"},
             // refine_passes: a loaded field keeps no photon statistics; estimate renders nothing to refine during.
             {R"(<integer name="refine_passes" value="-1"/>)", "refine_passes must be in [0, 32]"},
             {R"(<integer name="refine_passes" value="2"/><string name="estimate" value="incident"/>)",
              "refine_passes does not apply to estimate"},
             // Retired parameters (issue 48): an error naming the parameter and what replaced it.
             {R"(<string name="training" value="progressive"/>)", "training=\"progressive\" was retired"},
             {R"(<integer name="online_spp" value="8"/>)", "'online_spp' was retired"},
             {R"(<boolean name="selection_distance_method" value="true"/>)", "'selection_distance_method' was retired"},
             {R"(<float name="refine_gain" value="0.1"/>)", "'refine_gain' was retired"},
             {R"(<string name="hetero_distance" value="bins"/>)", "'hetero_distance' was retired"}}) {
        SCOPED_TRACE(c.params);
        const CliResult r = run(c.params);
        EXPECT_EQ(r.exit_code, 1);
        EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("s.xml:2"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir.file("o.exr")));
    }
    // The full system (the defaults) renders, with the contract's training="photons" too.
    const CliResult ok = run(R"(<integer name="photons" value="20000"/><string name="training" value="photons"/>)");
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

// refine_passes refines a photon field trained in this render: with a loaded field it is an error naming
// the file and line, and a given pre-pass (render --field) is refused before rendering.
TEST(GuidedVolPath, RefinementOfALoadedFieldIsAnError) {
    TempDir dir("refine-errors");
    const std::string field = dir.file("f.vgfield");
    const std::string photons = R"(<integrator type="guided_volpath"><integer name="photons" value="20000"/>)";
    const std::string save = point_light_scene(
        Point3f(0.f), 0.5f, 0.5f, photons + fmt::format(R"(<string name="save_field" value="{}"/></integrator>)", field));
    ASSERT_EQ(run_cli({"render", dir.write("save.xml", save), "-o", dir.file("s.exr"), "--spp", "1", "--quiet"}).exit_code, 0);
    const std::string load = point_light_scene(
        Point3f(0.f), 0.5f, 0.5f,
        photons + fmt::format(R"(<integer name="refine_passes" value="2"/><string name="load_field" value="{}"/></integrator>)",
                              field));
    CliResult r = run_cli({"render", dir.write("s.xml", load), "-o", dir.file("o.exr"), "--spp", "1", "--quiet"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("s.xml:2"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("refine_passes cannot refine a loaded field"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("o.exr")));
    const std::string scene = dir.write(
        "refine.xml", point_light_scene(Point3f(0.f), 0.5f, 0.5f,
                                        photons + R"(<integer name="refine_passes" value="2"/></integrator>)"));
    ASSERT_EQ(run_cli({"train", scene, "-o", dir.file("t.vgtrain"), "--quiet"}).exit_code, 0);
    r = run_cli({"render", scene, "--field", dir.file("t.vgtrain"), "-o", dir.file("o.exr"), "--spp", "1", "--quiet"});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("refine_passes"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("o.exr")));
}
