// The radiance probes (radiance_probe.h), the reference of tools/field_accuracy, against closed forms:
// at the centre of a purely absorbing unit sphere (sigma_t 1) under a uniform sky of radiance 1 and a
// point light, the radiance arriving from any direction is the sky's, attenuated: L_i = e^-1 (the point
// light is a delta: no walk sees it); the in-scattered radiance of the isotropic phase function adds
// the point light's direct light: L_s = e^-1 (1 + I / (4 pi r^2)), r its distance. A probe started in
// vacuum instead of in the sphere's medium would read 1; one that let the walk's first emitter hit be
// MIS-weighted against NEE, or double counted the point light, would miss the second.
#include <gtest/gtest.h>

#include <cmath>

#include "support/cli.h"
#include "support/running_stats.h"
#include "volguide/integrators/volpath/radiance_probe.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

using namespace volguide;

namespace {

constexpr float kProbeIntensity = 8.f, kProbeLightDistance = 2.f;

std::unique_ptr<Scene> probe_scene(const test::TempDir& dir) {
    const std::string xml = R"(<scene version="3.0.0">
    <integrator type="volpath"/>
    <medium type="homogeneous" id="absorber">
        <float name="sigma_t" value="1"/><float name="albedo" value="0"/><phase type="isotropic"/>
    </medium>
    <shape type="sphere"><bsdf type="null"/><ref name="interior" id="absorber"/></shape>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <emitter type="point"><point name="position" x="0" y="0" z="2"/><rgb name="intensity" value="8"/></emitter>
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
</scene>)";
    return load_scene(dir.write("probe.xml", xml));
}

template <class Sample>
void probe_expect_mean(double expected, int n, const Sample& sample) {
    test::RunningStats stats;
    for (int i = 0; i < n; ++i) stats.add(sample(i));
    const double se = std::sqrt(stats.variance() / n) + 1e-9;
    EXPECT_LT(std::abs(stats.mean() - expected) / se, 4.0) << stats.mean() << " ± " << se << " vs " << expected;
    EXPECT_NEAR(stats.mean(), expected, 0.02 * expected);
}

TEST(RadianceProbe, IncidentRadianceAtTheCentreOfAnAbsorbingSphere) {
    test::TempDir dir("radiance-probe");
    const std::unique_ptr<Scene> scene = probe_scene(dir);
    const Medium* medium = scene->shapes().front()->interior_medium();
    ASSERT_NE(medium, nullptr);
    const VolPathSettings settings;
    const Vec3f dirs[] = {{0, 0, 1}, {1, 0, 0}, normalize(Vec3f(-1, 2, -0.5f))};
    for (const Vec3f& w : dirs)
        probe_expect_mean(std::exp(-1.0), 40000, [&](int i) {
            Sampler s(7, 0, uint64_t(i));
            return double(incident_radiance_sample(*scene, settings, Point3f(0.f), medium, w, s).average());
        });
}

TEST(RadianceProbe, InscatteredRadianceAddsTheDeltaLightsDirectLight) {
    test::TempDir dir("radiance-probe");
    const std::unique_ptr<Scene> scene = probe_scene(dir);
    const Medium* medium = scene->shapes().front()->interior_medium();
    ASSERT_NE(medium, nullptr);
    const VolPathSettings settings;
    const double direct = kProbeIntensity / (4.0 * M_PI * kProbeLightDistance * kProbeLightDistance);
    probe_expect_mean(std::exp(-1.0) * (1.0 + direct), 80000, [&](int i) {
        Sampler s(9, 1, uint64_t(i));
        return double(inscattered_radiance_sample(*scene, settings, Point3f(0.f), *medium, Vec3f(0, 1, 0), s).average());
    });
}

}  // namespace
