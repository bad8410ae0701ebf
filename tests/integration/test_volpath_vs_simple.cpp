// volpath (NEE + MIS, optionally equiangular) against simple_volpath (free flights, phase/BSDF
// sampling only, emitters collected only when hit) on small scenes: the per-channel image means must
// agree (two-sample z-test, |z| < 4, standard errors from the per-sample variances of `moment`).
// Test media of support/test_media.h, so the integrators are compared independently of the media
// module.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "support/volpath_test_util.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// A chromatic medium in a sphere (boundary BSDF given), a large area light above, a diffuse floor,
// optionally a constant environment; the camera outside, or inside the medium.
std::string scene_xml(const std::string& integrator, const std::string& boundary, bool camera_inside,
                      bool environment, int max_depth) {
    const std::string camera_medium = camera_inside ? R"(<ref name="medium" id="m"/>)" : "";
    const std::string origin = camera_inside ? "0, 0.2, 0.5" : "0, 1, 4";
    return fmt::format(R"(<scene version="3.0.0">
    <integrator type="moment"><integrator type="{0}"><integer name="max_depth" value="{4}"/>{5}</integrator></integrator>
    {3}
    <medium type="homogeneous" id="m">
        <rgb name="sigma_t" value="1.5, 0.8, 2.5"/><rgb name="albedo" value="0.9, 0.7, 0.95"/>
        <phase type="hg"><float name="g" value="0.6"/></phase>
    </medium>
    <shape type="sphere">{1}<ref name="interior" id="m"/></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="1.5"/><rotate x="1" angle="90"/><translate y="2"/></transform>
        <emitter type="area"><rgb name="radiance" value="3, 2.5, 2"/></emitter>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/><translate y="-1.2"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.5, 0.4"/></bsdf>
    </shape>
    <sensor type="perspective">
        <float name="fov" value="50"/>{2}
        <transform name="to_world"><lookat origin="{6}" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
            <rfilter type="box"/></film>
    </sensor>
</scene>)",
                       integrator == "volpath_equiangular" ? "volpath" : integrator, boundary, camera_medium,
                       environment ? R"(<emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>)" : "",
                       max_depth,
                       integrator == "volpath_equiangular" ? R"(<boolean name="equiangular" value="true"/>)" : "",
                       origin);
}

void compare_boundary(const std::string& boundary, bool camera_inside, bool environment, int max_depth) {
    Rendered reference = render_scene_xml(scene_xml("simple_volpath", boundary, camera_inside, environment, max_depth),
                                          4096, 11);
    Rendered volpath =
        render_scene_xml(scene_xml("volpath", boundary, camera_inside, environment, max_depth), 1024, 12);
    Rendered equi = render_scene_xml(
        scene_xml("volpath_equiangular", boundary, camera_inside, environment, max_depth), 1024, 13);
    {
        SCOPED_TRACE("volpath vs simple_volpath");
        expect_same_means(volpath, reference);
    }
    {
        SCOPED_TRACE("volpath equiangular vs simple_volpath");
        expect_same_means(equi, reference);
    }
}

}  // namespace

TEST(VolPathVsSimple, NullBoundary) { compare_boundary(R"(<bsdf type="null"/>)", false, true, 5); }
TEST(VolPathVsSimple, NullBoundaryDepth2) { compare_boundary(R"(<bsdf type="null"/>)", false, false, 2); }
TEST(VolPathVsSimple, ThinDielectricBoundary) { compare_boundary(R"(<bsdf type="thindielectric"/>)", false, true, 4); }
TEST(VolPathVsSimple, DielectricBoundary) { compare_boundary(R"(<bsdf type="dielectric"/>)", false, true, 6); }
TEST(VolPathVsSimple, RoughDielectricBoundary) {
    compare_boundary(R"(<bsdf type="roughdielectric"><float name="alpha" value="0.3"/></bsdf>)", false, false, 5);
}
TEST(VolPathVsSimple, CameraInsideMedium) { compare_boundary(R"(<bsdf type="null"/>)", true, true, 4); }
