// Mitsuba 3's differentiable integrators read as their forward estimators (issue 40): a scene naming
// `prb` renders the image `path` renders and `prbvolpath` the image `volpath` renders, bit for bit at
// the same seed; `thinlens` renders (depth of field) and differs from the pinhole.
#include <gtest/gtest.h>

#include <fstream>

#include "support/cli.h"
#include "support/test_support.h"
#include "volguide/render/image_io.h"

using namespace volguide;
using namespace volguide::test;

namespace {

const char* kScene = R"(<scene version="3.0.0">
  <default name="integrator" value="path"/>
  <default name="sensor" value="perspective"/>
  <integrator type="$integrator"><integer name="max_depth" value="6"/></integrator>
  <sensor type="$sensor">
    <float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, -4, 1" target="0, 0, 0.3" up="0, 0, 1"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/></film>
  </sensor>
  <emitter type="constant"><rgb name="radiance" value="0.8"/></emitter>
  <shape type="rectangle"><transform name="to_world"><scale value="3"/></transform></shape>
  <shape type="sphere">
    <point name="center" value="0, 0, 0.6"/><float name="radius" value="0.5"/>
    <bsdf type="dielectric"/>
    <medium type="homogeneous" name="interior"><float name="sigma_t" value="2"/></medium>
  </shape>
</scene>
)";

Image render(TempDir& dir, const std::string& integrator, const std::string& extra = "") {
    const std::string xml = dir.file("scene.xml");
    std::ofstream(xml) << kScene;
    const std::string out = dir.file(integrator + extra + ".exr");
    std::vector<std::string> cmd = {"render", xml, "-o", out, "-D", "integrator=" + integrator, "--spp", "8",
                                    "--seed", "3", "--quiet"};
    if (!extra.empty()) cmd.insert(cmd.end(), {"-D", extra});
    CliResult r = run_cli(cmd);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return read_image(out);
}

}  // namespace

TEST(MitsubaAliases, PrbIsPathAndPrbVolpathIsVolpath) {
    TempDir dir("aliases");
    const Image path = render(dir, "path"), prb = render(dir, "prb");
    const Image volpath = render(dir, "volpath"), prbvolpath = render(dir, "prbvolpath");
    EXPECT_EQ(path.pixels, prb.pixels);
    EXPECT_EQ(volpath.pixels, prbvolpath.pixels);
    EXPECT_NE(path.pixels, volpath.pixels);  // the medium matters: the comparison can fail
}

TEST(MitsubaAliases, ThinLens) {
    TempDir dir("thinlens");
    std::string scene = kScene;
    const std::string from = "<sensor type=\"$sensor\">";
    scene.replace(scene.find(from), from.size(),
                  "<sensor type=\"thinlens\"><float name=\"aperture_radius\" value=\"0.3\"/>"
                  "<float name=\"focus_distance\" value=\"1.5\"/>");
    std::ofstream(dir.file("lens.xml")) << scene;
    CliResult r = run_cli({"render", dir.file("lens.xml"), "-o", dir.file("lens.exr"), "--spp", "8", "--seed", "3",
                           "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Image lens = read_image(dir.file("lens.exr")), pinhole = render(dir, "path");
    EXPECT_NE(lens.pixels, pinhole.pixels);  // out of focus: the aperture sample is used
    // Without aperture_radius a thin lens is an error at its line.
    scene = kScene;
    scene.replace(scene.find(from), from.size(), "<sensor type=\"thinlens\">");
    std::ofstream(dir.file("bad.xml")) << scene;
    r = run_cli({"render", dir.file("bad.xml"), "-o", dir.file("bad.exr"), "--spp", "1", "--quiet"});
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("bad.xml:5"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("aperture_radius"), std::string::npos) << r.err;
}
