// Single scattering from a point light in an infinite medium (oracles.md §5, exact): camera at the
// origin looking along +x, inside the medium (sensor `medium` reference), isotropic point light of
// intensity 4π at (1, 1, 0), σs = σt = 0.5, max_depth 2 (exactly one scattering event). Exercises
// the camera medium, NEE through a medium towards a delta light, and equiangular sampling with MIS.
// Test media of support/test_media.h; a 16 x 16 film with a tiny field of view (all pixels see the
// +x ray to within 1e-4 rad).
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "support/volpath_test_util.h"

using namespace volguide;
using namespace volguide::test;

namespace {

std::string single_scatter_xml(const std::string& phase, bool equiangular, const std::string& light = "point") {
    const std::string light_xml =
        light == "point"
            ? R"(<emitter type="point"><point name="position" x="1" y="1" z="0"/>
                 <rgb name="intensity" value="12.566370614359172"/><ref name="medium" id="m"/></emitter>)"
            : R"(<emitter type="spot"><rgb name="intensity" value="12.566370614359172"/>
                 <float name="cutoff_angle" value="89"/><float name="beam_width" value="89"/>
                 <transform name="to_world"><lookat origin="1, 1, 0" target="1, 0, 0" up="1, 0, 0"/></transform>
                 </emitter>)";
    return fmt::format(R"(<scene version="3.0.0">
    <integrator type="moment"><integrator type="volpath"><integer name="max_depth" value="2"/>
        <boolean name="equiangular" value="{1}"/></integrator></integrator>
    <medium type="homogeneous" id="m"><float name="sigma_t" value="0.5"/><float name="albedo" value="1"/>{0}</medium>
    {2}
    <sensor type="perspective">
        <float name="fov" value="0.01"/><float name="near_clip" value="1e-6"/><float name="far_clip" value="1e7"/>
        <ref name="medium" id="m"/>
        <transform name="to_world"><lookat origin="0, 0, 0" target="1, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/></film>
    </sensor>
</scene>)",
                       phase, equiangular ? "true" : "false", light_xml);
}

void expect_value(const std::string& xml, double expected, uint64_t seed) {
    Rendered r = render_scene_xml(xml, 1024, seed);
    ChannelMean m = channel_mean(r);
    EXPECT_NEAR(m.mean, expected, 4 * m.se + 2e-4 * expected) << m.mean << " ± " << m.se;
    std::printf("value %.6f ± %.6f (expected %.6f)\n", m.mean, m.se, expected);
}

const char* kIsotropic = R"(<phase type="isotropic"/>)";
const char* kHG = R"(<phase type="hg"><float name="g" value="0.5"/></phase>)";

}  // namespace

TEST(VolPathSingleScatter, IsotropicDistanceSampling) { expect_value(single_scatter_xml(kIsotropic, false), 0.30621153, 1); }
TEST(VolPathSingleScatter, IsotropicEquiangular) { expect_value(single_scatter_xml(kIsotropic, true), 0.30621153, 2); }
TEST(VolPathSingleScatter, HGDistanceSampling) { expect_value(single_scatter_xml(kHG, false), 0.2277334439, 3); }
TEST(VolPathSingleScatter, HGEquiangular) { expect_value(single_scatter_xml(kHG, true), 0.2277334439, 4); }

// Equiangular sampling must reduce the variance of this single-scattering estimate markedly.
TEST(VolPathSingleScatter, EquiangularReducesVariance) {
    Rendered plain = render_scene_xml(single_scatter_xml(kIsotropic, false), 256, 5);
    Rendered equi = render_scene_xml(single_scatter_xml(kIsotropic, true), 256, 6);
    double var_plain = 0, var_equi = 0;
    for (size_t i = 0; i < plain.var.pixels.size(); ++i) {
        var_plain += plain.var.pixels[i][0];
        var_equi += equi.var.pixels[i][0];
    }
    EXPECT_LT(var_equi, 0.5 * var_plain) << "per-sample variance " << var_equi << " vs " << var_plain;
}

// A spot light whose cone (89°) covers every point that matters gives the same value.
TEST(VolPathSingleScatter, SpotEquiangular) {
    expect_value(single_scatter_xml(kHG, true, "spot"), 0.2277334439, 7);
}
