// The guiding field's camera estimate (guided_volpath `estimate`, cache_estimate.h) against closed
// forms: a field with uniform incident radiance Phi / (4 pi) in a cube [-1, 1]^3 of homogeneous
// medium gives, along a ray with chord length s inside the cube,
//   integral of T sigma_s Phi / (4 pi) = Phi / (4 pi) sigma_s / sigma_t (1 - e^(-sigma_t s))
// for both quantities and any phase function; a heterogeneous grid of the same constant density
// gives the same; nothing is added behind an opaque surface. And volpath's volume_only image: black
// without media, identical to the full image when every light path scatters first in the medium.
#include <gtest/gtest.h>

#include <cmath>

#include "support/cli.h"
#include "support/vol_writer.h"
#include "support/volpath_test_util.h"
#include "volguide/integrators/guided/estimates/cache_estimate.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

namespace volguide {
namespace {

// The cube of medium `medium` (XML of a <medium id="m">), optionally an opaque wall at z = 3.
std::string cache_cube_scene(const std::string& medium, bool wall) {
    return R"(<scene version="3.0.0">
    <integrator type="volpath"/>
    <sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, -6" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
)" + medium + R"(
    <shape type="cube"><bsdf type="null"/><ref name="interior" id="m"/></shape>
)" + (wall ? R"(    <shape type="rectangle"><transform name="to_world"><scale value="4"/><translate z="0.5"/></transform></shape>
)"
           : "") +
           "</scene>\n";
}

const char* kHomogeneous = R"(<medium type="homogeneous" id="m"><rgb name="sigma_t" value="0.5, 1, 2"/>
        <rgb name="albedo" value="0.8, 0.5, 0.9"/><phase type="hg"><float name="g" value="0.7"/></phase></medium>)";

// One field leaf per half of the cube (split at x = 0), uniform incident radiance, fluence Phi.
GuidingField uniform_field(Color3 phi) {
    std::vector<Point3f> points;
    for (int i = 0; i < 64; ++i) points.push_back(Point3f(i < 32 ? -0.5f : 0.5f, 0.f, 0.f));
    SpatialTreeSettings ts;
    ts.max_samples = 32;
    SpatialTree tree = SpatialTree::build(BBox3f(Point3f(-1.01f), Point3f(1.01f)), points, ts);
    std::vector<GuidingLeaf> leaves(size_t(tree.leaf_count()));
    for (GuidingLeaf& leaf : leaves) {
        leaf.vmm.add_lobe(1.f, VmfLobe(Vec3f(0.f, 0.f, 1.f), 0.f));  // kappa 0: uniform
        leaf.fluence = phi;
        leaf.samples = 100;
        leaf.valid = true;
    }
    return GuidingField(std::move(tree), std::move(leaves));
}

Color3 expected(Color3 phi, Color3 sigma_t, Color3 albedo, float chord) {
    Color3 r;
    for (int c = 0; c < 3; ++c)
        r[c] = phi[c] * InvFourPi * albedo[c] * -std::expm1(-sigma_t[c] * chord);
    return r;
}

void expect_close(Color3 got, Color3 want, float rel) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], rel * want[c] + 1e-7f) << "channel " << c;
}

TEST(CacheEstimate, HomogeneousCubeMatchesTheClosedForm) {
    test::TempDir dir("cache-estimate");
    auto scene = load_scene(dir.write("s.xml", cache_cube_scene(kHomogeneous, false)));
    const Color3 phi(2.f, 3.f, 1.f);
    const GuidingField field = uniform_field(phi);
    ASSERT_EQ(field.tree().leaf_count(), 2);
    CacheEstimator estimator(*scene, field);
    Sampler sampler(1, 0, 0);
    const Color3 sigma_t(0.5f, 1.f, 2.f), albedo(0.8f, 0.5f, 0.9f);
    // Straight through (chord 2), crossing both leaves; and a diagonal ray (chord 2 sqrt 3).
    const Ray straight(Point3f(0.f, 0.3f, -6.f), Vec3f(0.f, 0.f, 1.f));
    const Ray diagonal(Point3f(-3.f, -3.f, -3.f), normalize(Vec3f(1.f, 1.f, 1.f)));
    for (CacheQuantity q : {CacheQuantity::Inscattered, CacheQuantity::Incident}) {
        expect_close(estimator.estimate(straight, nullptr, q, sampler), expected(phi, sigma_t, albedo, 2.f), 1e-4f);
        expect_close(estimator.estimate(diagonal, nullptr, q, sampler),
                     expected(phi, sigma_t, albedo, 2.f * std::sqrt(3.f)), 1e-4f);
    }
    // A ray that misses the cube sees nothing; one starting inside sees the rest of its chord.
    EXPECT_EQ(estimator.estimate(Ray(Point3f(5.f, 5.f, -6.f), Vec3f(0.f, 0.f, 1.f)), nullptr,
                                 CacheQuantity::Inscattered, sampler),
              Color3(0.f));
    expect_close(estimator.estimate(Ray(Point3f(0.2f, 0.f, 0.f), Vec3f(0.f, 0.f, 1.f)), scene->shapes()[0]->interior_medium(),
                                    CacheQuantity::Inscattered, sampler),
                 expected(phi, sigma_t, albedo, 1.f), 1e-4f);
}

TEST(CacheEstimate, OpaqueSurfaceEndsTheMarch) {
    test::TempDir dir("cache-estimate-wall");
    auto scene = load_scene(dir.write("s.xml", cache_cube_scene(kHomogeneous, true)));
    const Color3 phi(1.f);
    const GuidingField field = uniform_field(phi);
    CacheEstimator estimator(*scene, field);
    Sampler sampler(1, 0, 0);
    // The wall at z = 0.5 cuts the chord to 1.5.
    expect_close(estimator.estimate(Ray(Point3f(0.f, 0.f, -6.f), Vec3f(0.f, 0.f, 1.f)), nullptr,
                                    CacheQuantity::Inscattered, sampler),
                 expected(phi, Color3(0.5f, 1.f, 2.f), Color3(0.8f, 0.5f, 0.9f), 1.5f), 1e-4f);
}

TEST(CacheEstimate, ConstantGridMatchesTheHomogeneousMedium) {
    test::TempDir dir("cache-estimate-grid");
    test::VolGrid grid = test::make_vol_grid(4, 4, 4, 1, [](float, float, float, int) { return 1.f; });
    test::write_vol_file(dir.file("d.vol"), grid);
    const std::string medium = R"(<medium type="heterogeneous" id="m">
        <volume name="sigma_t" type="gridvolume"><string name="filename" value="d.vol"/>
            <transform name="to_world"><scale value="2"/><translate x="-1" y="-1" z="-1"/></transform></volume>
        <rgb name="albedo" value="0.8, 0.5, 0.9"/><float name="scale" value="1.5"/></medium>)";
    auto scene = load_scene(dir.write("s.xml", cache_cube_scene(medium, false)));
    const Color3 phi(2.f, 3.f, 1.f);
    const GuidingField field = uniform_field(phi);
    CacheEstimator estimator(*scene, field);
    Sampler sampler(1, 0, 0);
    for (CacheQuantity q : {CacheQuantity::Inscattered, CacheQuantity::Incident})
        expect_close(estimator.estimate(Ray(Point3f(0.1f, -0.2f, -6.f), Vec3f(0.f, 0.f, 1.f)), nullptr, q, sampler),
                     expected(phi, Color3(1.5f), Color3(0.8f, 0.5f, 0.9f), 2.f), 2e-4f);
}

// A fog sphere lit by a point light, seen against nothing: every contribution comes from a path
// whose first event is a scattering in the fog, so the volume-only image is the full image.
std::string fog_scene(bool volume_only, bool wall) {
    return std::string(R"(<scene version="3.0.0">
    <integrator type="volpath"><boolean name="volume_only" value=")") +
           (volume_only ? "true" : "false") + R"("/></integrator>
    <sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, -5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>
    <emitter type="point"><point name="position" x="2" y="2" z="0"/><rgb name="intensity" value="10"/></emitter>
    <medium type="homogeneous" id="m"><rgb name="sigma_t" value="0.5"/><rgb name="albedo" value="0.9"/></medium>
    <shape type="sphere"><bsdf type="null"/><ref name="interior" id="m"/></shape>
)" + (wall ? R"(    <shape type="rectangle"><transform name="to_world"><scale value="5"/><rotate y="1" angle="180"/><translate z="2"/></transform></shape>
)"
           : "") +
           "</scene>\n";
}

TEST(VolPathVolumeOnly, EqualsTheFullImageWhenAllLightScattersFirstInTheMedium) {
    const test::Rendered full = test::render_scene_xml(fog_scene(false, false), 16, 3, false);
    const test::Rendered v = test::render_scene_xml(fog_scene(true, false), 16, 3, false);
    ASSERT_EQ(full.mean.pixels.size(), v.mean.pixels.size());
    double sum = 0;
    for (size_t i = 0; i < v.mean.pixels.size(); ++i) {
        EXPECT_EQ(full.mean.pixels[i], v.mean.pixels[i]) << i;
        sum += v.mean.pixels[i].g;
    }
    EXPECT_GT(sum, 0.0);
    // With a lit wall behind, the wall's direct view is excluded: less light, still some.
    const test::Rendered wall_full = test::render_scene_xml(fog_scene(false, true), 16, 3, false);
    const test::Rendered wall_v = test::render_scene_xml(fog_scene(true, true), 16, 3, false);
    double a = 0, b = 0;
    for (size_t i = 0; i < wall_v.mean.pixels.size(); ++i) a += wall_full.mean.pixels[i].g, b += wall_v.mean.pixels[i].g;
    EXPECT_GT(b, 0.0);
    EXPECT_LT(b, 0.8 * a);
}

// End to end: guided_volpath's estimate=inscattered image of a forward-scattering fog sphere lit from
// the side agrees with the volume-only render it predicts (whole-image mean; the field is piecewise
// constant, so single pixels may differ more). Measured estimate / render over photon seeds 5, 13,
// 21, 34: 0.98-1.07 for g = 0 and 1.07-1.14 for g = 0.7 (the A3 convolution and the leaves'
// piecewise-constant radiance); before the leaves' medium fractions were applied both read ~0.6.
std::string estimate_scene(const std::string& integrator, float g) {
    return R"(<scene version="3.0.0">
    )" + integrator + R"(
    <sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, -5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>
    <emitter type="point"><point name="position" x="0.5" y="0" z="2.5"/><rgb name="intensity" value="10"/></emitter>
    <medium type="homogeneous" id="m"><rgb name="sigma_t" value="0.5"/><rgb name="albedo" value="0.9"/>
        <phase type="hg"><float name="g" value=")" + std::to_string(g) + R"("/></phase></medium>
    <shape type="sphere"><bsdf type="null"/><ref name="interior" id="m"/></shape>
</scene>
)";
}

double image_mean(const Image& img) {
    double s = 0;
    for (const Color3& c : img.pixels) s += c.g;
    return s / double(img.pixels.size());
}

TEST(CacheEstimate, GuidedVolPathEstimateMatchesTheVolumeOnlyImage) {
    const std::string guided = R"(<integrator type="guided_volpath"><string name="estimate" value="inscattered"/>
        <integer name="photons" value="400000"/><integer name="leaf_samples" value="1000"/>
        <string name="distance" value="standard"/><string name="direction" value="phase"/><string name="rrs" value="standard"/></integrator>)";
    const std::string vonly = R"(<integrator type="volpath"><boolean name="volume_only" value="true"/></integrator>)";
    for (float g : {0.f, 0.7f}) {
        const double est = image_mean(test::render_scene_xml(estimate_scene(guided, g), 4, 5, false).mean);
        const double ref = image_mean(test::render_scene_xml(estimate_scene(vonly, g), 256, 5, false).mean);
        ASSERT_GT(ref, 0.0);
        EXPECT_NEAR(est / ref, 1.0, g > 0.f ? 0.2 : 0.1) << "g " << g << ": estimate " << est << ", volume-only render " << ref;
    }
}

// White furnace (albedo 1 in a constant environment of radiance 1: L = 1 everywhere) seen by an
// orthographic camera through 2 units of medium: the volume-only image is 1 - e^(-2 sigma_t) in every
// pixel, with the phase function or with a forward delta at the first vertex alike.
TEST(VolPathVolumeOnly, FurnaceMatchesTheClosedFormWithAndWithoutForwardFirstScatter) {
    for (const char* forward : {"false", "true"}) {
        const std::string xml = std::string(R"(<scene version="3.0.0">
    <integrator type="volpath"><boolean name="volume_only" value="true"/>
        <boolean name="forward_first_scatter" value=")") + forward + R"("/></integrator>
    <sensor type="orthographic"><transform name="to_world"><scale x="0.5" y="0.5"/>
        <lookat origin="0, 0, -5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>
    <emitter type="constant"/>
    <medium type="homogeneous" id="m"><rgb name="sigma_t" value="0.6"/><rgb name="albedo" value="1"/>
        <phase type="hg"><float name="g" value="0.5"/></phase></medium>
    <shape type="cube"><bsdf type="null"/><ref name="interior" id="m"/></shape>
</scene>
)";
        const test::Rendered r = test::render_scene_xml(xml, 1024, 9, false);
        // Every pixel has the same expectation: test the pixel mean with the pixels' own spread.
        double sum = 0, sum2 = 0;
        for (const Color3& c : r.mean.pixels) sum += c.g, sum2 += double(c.g) * c.g;
        const double n = double(r.mean.pixels.size()), mean = sum / n;
        const double se = std::sqrt(std::max(sum2 / n - mean * mean, 0.0) / n);
        const double want = 1.0 - std::exp(-2.0 * 0.6);
        EXPECT_NEAR(mean, want, 4 * se + 1e-4) << "forward_first_scatter " << forward << ", se " << se;
        EXPECT_GT(se, 0.0);
    }
}

TEST(VolPathVolumeOnly, BlackWithoutMedia) {
    const std::string xml = R"(<scene version="3.0.0">
    <integrator type="volpath"><boolean name="volume_only" value="true"/></integrator>
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
    <emitter type="constant"/>
    <shape type="sphere"><transform name="to_world"><translate z="4"/></transform></shape>
</scene>
)";
    const test::Rendered r = test::render_scene_xml(xml, 8, 1, false);
    for (const Color3& c : r.mean.pixels) EXPECT_EQ(c, Color3(0.f));
}

}  // namespace
}  // namespace volguide
