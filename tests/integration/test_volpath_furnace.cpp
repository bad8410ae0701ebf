// White furnace (oracles.md §1) for the volumetric integrators: a constant environment of radiance 1
// and an albedo-1 medium inside a sphere; every pixel has mean exactly 1 whatever the boundary
// (null, thindielectric, dielectric), the phase function and the integrator. Uses the test media of
// support/test_media.h so the integrator is tested independently of the media module.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "support/volpath_test_util.h"

using namespace volguide;
using namespace volguide::test;

namespace {

std::string furnace_xml(const std::string& integrator, const std::string& boundary_bsdf, float g,
                        const std::string& extra_integrator = "") {
    return fmt::format(R"(<scene version="3.0.0">
    <integrator type="moment"><integrator type="{0}">{3}</integrator></integrator>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <medium type="homogeneous" id="m">
        <rgb name="sigma_t" value="2, 1, 3"/><rgb name="albedo" value="1"/>
        <phase type="hg"><float name="g" value="{2}"/></phase>
    </medium>
    <shape type="sphere">{1}<ref name="interior" id="m"/></shape>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="12"/><integer name="height" value="12"/>
            <rfilter type="box"/></film>
    </sensor>
</scene>)",
                       integrator, boundary_bsdf, g, extra_integrator);
}

}  // namespace

TEST(VolPathFurnace, NullBoundaryForwardScattering) {
    Rendered r = render_scene_xml(furnace_xml("volpath", R"(<bsdf type="null"/>)", 0.9f), 256, 1);
    expect_constant_image(r, 1.0);
}

TEST(VolPathFurnace, NullBoundaryBackwardScattering) {
    Rendered r = render_scene_xml(furnace_xml("volpath", R"(<bsdf type="null"/>)", -0.9f), 256, 2);
    expect_constant_image(r, 1.0);
}

TEST(VolPathFurnace, ThinDielectricBoundary) {
    Rendered r = render_scene_xml(furnace_xml("volpath", R"(<bsdf type="thindielectric"/>)", 0.5f), 256, 3);
    expect_constant_image(r, 1.0);
}

TEST(VolPathFurnace, DielectricBoundary) {
    Rendered r = render_scene_xml(furnace_xml("volpath", R"(<bsdf type="dielectric"/>)", 0.f), 1024, 4);
    expect_constant_image(r, 1.0);
}

TEST(VolPathFurnace, Equiangular) {
    // No point/area light: equiangular finds no target and must not change anything.
    Rendered r = render_scene_xml(
        furnace_xml("volpath", R"(<bsdf type="null"/>)", 0.9f, R"(<boolean name="equiangular" value="true"/>)"), 256,
        5);
    expect_constant_image(r, 1.0);
}

TEST(VolPathFurnace, SimpleVolPath) {
    Rendered r = render_scene_xml(furnace_xml("simple_volpath", R"(<bsdf type="null"/>)", 0.9f), 256, 6);
    expect_constant_image(r, 1.0);
}
