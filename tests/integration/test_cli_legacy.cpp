// Mitsuba 0.6 scenes through the CLI (issue 50): a 0.6 scene with a homogeneous and a heterogeneous
// medium, an ldrfilm, a low-discrepancy sampler, a bitmap texture, a rough dielectric and an area light
// renders the image of its hand-written Mitsuba 3 form bit for bit at the same seed (EXR and the
// ldrfilm's PNG); `volguide upgrade` writes a file that renders the same EXR and keeps the comments;
// errors name the 0.6 file's lines.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "support/cli.h"
#include "support/test_support.h"
#include "support/vol_writer.h"
#include "volguide/render/image_io.h"
#include "volguide/render/srgb.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// The 0.6 scene. Its numbers are chosen so that what the upgrade computes is exact in binary (sigma_t
// 2, albedo 0.75; the grid's 5 voxels over [0, 4] per axis become the unit cube scaled by 5 and moved
// by -0.5), so the hand-written form below can state them.
const char* kScene06 = R"(<?xml version="1.0" encoding="utf-8"?>
<!-- Mitsuba 0.6: the acceptance scene of issue 50 -->
<scene version="0.6.0">
    <integrator type="volpath">
        <integer name="maxDepth" value="10"/>
        <boolean name="strictNormals" value="false"/>
    </integrator>

    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="toWorld">
            <lookAt origin="0, -7, 2.5" target="0, 0, 0.8" up="0, 0, 1"/>
        </transform>
        <sampler type="ldsampler">
            <integer name="sampleCount" value="8"/>
        </sampler>
        <film type="ldrfilm">
            <integer name="width" value="40"/>
            <integer name="height" value="30"/>
            <float name="exposure" value="1"/>
            <boolean name="banner" value="false"/>
            <rfilter type="tent"/>
        </film>
    </sensor>

    <!-- the floor, textured -->
    <shape type="rectangle">
        <transform name="toWorld"><scale value="4"/></transform>
        <bsdf type="diffuse">
            <texture type="bitmap" name="reflectance">
                <string name="filename" value="checker.png"/>
                <float name="uscale" value="4"/>
                <float name="vscale" value="4"/>
            </texture>
        </bsdf>
    </shape>

    <!-- rough glass around a homogeneous medium -->
    <shape type="sphere">
        <point name="center" x="-1.2" y="0" z="0.8"/>
        <float name="radius" value="0.8"/>
        <bsdf type="roughdielectric">
            <string name="distribution" value="ggx"/>
            <float name="alpha" value="0.15"/>
            <string name="intIOR" value="bk7"/>
        </bsdf>
        <medium type="homogeneous" name="interior">
            <spectrum name="sigmaA" value="0.5"/>
            <spectrum name="sigmaS" value="1.5"/>
            <phase type="hg"><float name="g" value="0.6"/></phase>
        </medium>
    </shape>

    <!-- a box of smoke: 0.6 makes a medium boundary without BSDF index-matched -->
    <medium type="heterogeneous" id="smoke">
        <volume name="density" type="gridvolume">
            <string name="filename" value="smoke.vol"/>
            <transform name="toWorld"><translate x="-0.8" y="-2" z="0"/></transform>
        </volume>
        <volume name="albedo" type="constvolume">
            <spectrum name="value" value="0.8"/>
        </volume>
        <float name="scale" value="2"/>
    </medium>
    <shape type="cube">
        <transform name="toWorld"><scale value="2"/><translate x="1.2" y="0" z="2"/></transform>
        <ref name="interior" id="smoke"/>
    </shape>

    <!-- the light: 0.6 makes an emitter without BSDF black -->
    <shape type="rectangle">
        <transform name="toWorld"><scale value="0.8"/><rotate x="1" angle="180"/><translate z="4.5"/></transform>
        <emitter type="area"><spectrum name="radiance" value="12"/></emitter>
    </shape>
</scene>
)";

// The same scene written by hand in Mitsuba 3's form (with volguide's ldrfilm, Mitsuba 0.6's film).
const char* kScene3 = R"(<scene version="3.0.0">
    <integrator type="volpath"><integer name="max_depth" value="10"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, -7, 2.5" target="0, 0, 0.8" up="0, 0, 1"/></transform>
        <sampler type="ldsampler"><integer name="sample_count" value="8"/></sampler>
        <film type="ldrfilm">
            <integer name="width" value="40"/><integer name="height" value="30"/>
            <float name="exposure" value="1"/>
            <rfilter type="tent"/>
        </film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="4"/></transform>
        <bsdf type="diffuse">
            <texture type="bitmap" name="reflectance">
                <string name="filename" value="checker.png"/>
                <string name="format" value="fp16"/>
                <transform name="to_uv"><scale x="4" y="4"/></transform>
            </texture>
        </bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" x="-1.2" y="0" z="0.8"/><float name="radius" value="0.8"/>
        <bsdf type="roughdielectric">
            <string name="distribution" value="ggx"/><float name="alpha" value="0.15"/>
            <string name="int_ior" value="bk7"/>
        </bsdf>
        <medium type="homogeneous" name="interior">
            <rgb name="sigma_t" value="2"/><rgb name="albedo" value="0.75"/>
            <phase type="hg"><float name="g" value="0.6"/></phase>
        </medium>
    </shape>
    <medium type="heterogeneous" id="smoke">
        <volume name="sigma_t" type="gridvolume">
            <string name="filename" value="smoke.vol"/>
            <transform name="to_world"><scale value="5"/><translate value="-0.5"/>
                <translate x="-0.8" y="-2" z="0"/></transform>
        </volume>
        <volume name="albedo" type="constvolume"><spectrum name="value" value="0.8"/></volume>
        <float name="scale" value="2"/>
    </medium>
    <shape type="cube">
        <transform name="to_world"><scale value="2"/><translate x="1.2" y="0" z="2"/></transform>
        <ref name="interior" id="smoke"/>
        <bsdf type="null"/>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.8"/><rotate x="1" angle="180"/><translate z="4.5"/></transform>
        <emitter type="area"><rgb name="radiance" value="12"/></emitter>
        <bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf>
    </shape>
</scene>
)";

// The data files: a checker texture and a 5^3 density grid over [0, 4]^3 with zero outer voxels.
void write_assets(const TempDir& dir) {
    Image checker(4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) checker.at(x, y) = (x + y) % 2 ? Color3(0.8f, 0.7f, 0.2f) : Color3(0.1f, 0.2f, 0.6f);
    write_png(dir.file("checker.png"), checker);
    VolGrid g = make_vol_grid(5, 5, 5, 1, [](float x, float y, float z, int) {
        const bool inner = x > 0.2f && x < 0.8f && y > 0.2f && y < 0.8f && z > 0.2f && z < 0.8f;
        return inner ? 0.5f + x : 0.f;
    });
    const float box[6] = {0, 0, 0, 4, 4, 4};
    std::copy(box, box + 6, g.bbox);
    write_vol_file(dir.file("smoke.vol"), g);
}

CliResult render_to(const std::string& scene, const std::string& stem, const std::string& dir) {
    return run_cli({"render", scene, "-o", dir + "/" + stem + ".exr", "-o", dir + "/" + stem + ".png", "--seed", "7",
                    "--quiet"});
}

int line_of(const std::string& text, const std::string& needle) {
    const size_t at = text.find(needle);
    return at == std::string::npos ? -1 : 1 + int(std::count(text.begin(), text.begin() + long(at), '\n'));
}

}  // namespace

TEST(CliLegacy, Mitsuba06SceneRendersItsMitsuba3Form) {
    TempDir dir("legacy_accept");
    write_assets(dir);
    const std::string s06 = dir.write("scene06.xml", kScene06), s3 = dir.write("scene3.xml", kScene3);
    CliResult a = render_to(s06, "a", dir.path().string()), b = render_to(s3, "b", dir.path().string());
    ASSERT_EQ(a.exit_code, 0) << a.err;
    ASSERT_EQ(b.exit_code, 0) << b.err;
    const Image ia = read_image(dir.file("a.exr")), ib = read_image(dir.file("b.exr"));
    EXPECT_EQ(ia.pixels, ib.pixels);
    EXPECT_EQ(read_file(dir.file("a.png")), read_file(dir.file("b.png")));
    // The ldrfilm's exposure of one stop is in the PNG (not in the EXR).
    const Image png = read_image(dir.file("a.png"), /*raw=*/true);
    const Color3 linear = ia.at(20, 20);
    EXPECT_NEAR(png.at(20, 20).r, linear_to_srgb(std::clamp(2 * linear.r, 0.f, 1.f)), 0.6f / 255) << linear.r;
    // What the 0.6 file names is said once: the sampler (ldsampler, sampled independently) and the EWA filter.
    const std::string sampler = fmt::format("scene06.xml:{}: sampler 'ldsampler' is sampled independently",
                                            line_of(kScene06, "<sampler type=\"ldsampler\">"));
    const std::string bitmap = fmt::format("scene06.xml:{}: Mitsuba 0.6 filters this bitmap with EWA",
                                           line_of(kScene06, "<texture type=\"bitmap\""));
    EXPECT_NE(a.err.find(sampler), std::string::npos) << a.err;
    EXPECT_NE(a.err.find(bitmap), std::string::npos) << a.err;
    // The comparison can fail: a different albedo in the smoke renders a different image.
    std::string changed = kScene3;
    changed.replace(changed.find("value=\"0.8\"/></volume>"), 11, "value=\"0.6\"");
    CliResult c = render_to(dir.write("scene3b.xml", changed), "c", dir.path().string());
    ASSERT_EQ(c.exit_code, 0) << c.err;
    EXPECT_NE(read_image(dir.file("c.exr")).pixels, ia.pixels);
}

TEST(CliLegacy, UpgradeWritesMitsuba3sForm) {
    TempDir dir("legacy_upgrade");
    write_assets(dir);
    const std::string s06 = dir.write("scene06.xml", kScene06), out = dir.file("upgraded.xml");
    CliResult u = run_cli({"upgrade", s06, "-o", out});
    ASSERT_EQ(u.exit_code, 0) << u.err;
    const std::string text = read_file(out);
    // Mitsuba 3 has no ldrfilm: an hdrfilm, and the lost tonemap is said at the film's line.
    EXPECT_NE(u.err.find(fmt::format("scene06.xml:{}: Mitsuba 3 has no ldrfilm", line_of(kScene06, "<film type="))),
              std::string::npos)
        << u.err;
    EXPECT_NE(u.err.find("exposure=1"), std::string::npos) << u.err;
    EXPECT_EQ(text.find("ldrfilm"), std::string::npos) << text;
    EXPECT_EQ(text.find("sigmaA"), std::string::npos) << text;
    EXPECT_NE(text.find("<scene version=\"3.0.0\">"), std::string::npos) << text;
    // Comments and untouched lines are kept as written, renamed parameters in their places; what 0.6's
    // default meant (strictNormals false, no banner) is gone with its line.
    for (const char* kept : {"<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!-- Mitsuba 0.6: the acceptance scene of issue 50 -->\n",
                             "\n\n    <!-- the floor, textured -->\n    <shape type=\"rectangle\">\n",
                             "    <integrator type=\"volpath\">\n        <integer name=\"max_depth\" value=\"10\"/>\n"
                             "    </integrator>\n",
                             "        <float name=\"radius\" value=\"0.8\"/>\n",
                             "            <phase type=\"hg\"><float name=\"g\" value=\"0.6\"/></phase>\n"}) {
        EXPECT_NE(text.find(kept), std::string::npos) << kept << "\n" << text;
    }
    // Rendered, it is the 0.6 scene's EXR bit for bit.
    CliResult a = render_to(s06, "a", dir.path().string()), b = render_to(out, "b", dir.path().string());
    ASSERT_EQ(a.exit_code, 0) << a.err;
    ASSERT_EQ(b.exit_code, 0) << b.err;
    EXPECT_EQ(read_image(dir.file("a.exr")).pixels, read_image(dir.file("b.exr")).pixels);
    // Upgrading a file that is not a 0.x file is an error; the input as output a usage error.
    CliResult again = run_cli({"upgrade", out, "-o", dir.file("twice.xml")});
    EXPECT_EQ(again.exit_code, 1);
    EXPECT_NE(again.err.find(fmt::format("upgraded.xml:{}: not a Mitsuba 0.x file", line_of(text, "<scene"))),
              std::string::npos)
        << again.err;
    CliResult same = run_cli({"upgrade", s06, "-o", s06});
    EXPECT_EQ(same.exit_code, 2) << same.err;
}

TEST(CliLegacy, ErrorsNameTheZeroSixFilesLine) {
    TempDir dir("legacy_errors");
    write_assets(dir);
    std::string scene = kScene06;
    const std::string ggx = "<string name=\"distribution\" value=\"ggx\"/>";
    scene.replace(scene.find(ggx), ggx.size(), "<string name=\"distribution\" value=\"phong\"/>");
    const std::string f = dir.write("bad06.xml", scene);
    const std::string expected = fmt::format("bad06.xml:{}: the Phong microfacet distribution has no equivalent",
                                             line_of(scene, "value=\"phong\""));
    for (const char* command : {"render", "upgrade"}) {
        CliResult r = std::string(command) == "render" ? run_cli({"render", f, "-o", dir.file("x.exr"), "--quiet"})
                                                        : run_cli({"upgrade", f, "-o", dir.file("x.xml")});
        EXPECT_EQ(r.exit_code, 1) << command;
        EXPECT_NE(r.err.find(expected), std::string::npos) << command << ": " << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir.file("x.exr")) || std::filesystem::exists(dir.file("x.xml")));
    }
}
