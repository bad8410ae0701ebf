// Strict input handling through the CLI (issue 2): malformed scenes and command lines exit with
// the right code, print exactly one line `volguide: FILE:LINE: message`, and write no output.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "support/cli.h"

using namespace volguide::test;
namespace fs = std::filesystem;

namespace {

// A minimal valid scene; {BODY} is replaced by the case's shapes. Lines are counted from 1.
const std::string kHeader = R"(<scene version="3.0.0">
    <default name="spp" value="4"/>
    <sensor type="perspective">
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
    </sensor>
)";  // 6 lines: the case body starts on line 7

struct BadScene {
    const char* name;
    std::string body;       // appended after kHeader, followed by </scene>
    int line;               // expected line of the error (in scene.xml unless file is set)
    const char* fragment;   // expected in the message (case-insensitive match not needed)
    std::vector<std::string> extra_args = {};
    const char* file = "scene.xml";
};

std::vector<BadScene> bad_scenes() {
    return {
        {"unknown_plugin", "    <shape type=\"sphere\"><bsdf type=\"difuse\"/></shape>\n", 7, "difuse"},
        {"misspelled_parameter",
         "    <shape type=\"sphere\">\n        <bsdf type=\"diffuse\"><rgb name=\"reflectanse\" value=\"0.5\"/></bsdf>\n"
         "    </shape>\n",
         8, "reflectanse"},
        {"unused_shape_parameter", "    <shape type=\"sphere\">\n        <float name=\"radios\" value=\"1\"/>\n    </shape>\n",
         8, "radios"},
        {"missing_mesh_file", "    <shape type=\"obj\">\n        <string name=\"filename\" value=\"nowhere.obj\"/>\n    </shape>\n",
         8, "nowhere.obj"},
        {"bad_number", "    <shape type=\"sphere\"><float name=\"radius\" value=\"1.0x\"/></shape>\n", 7, "1.0x"},
        {"negative_radius", "    <shape type=\"sphere\"><float name=\"radius\" value=\"-2\"/></shape>\n", 7, "radius"},
        {"unknown_ref", "    <shape type=\"sphere\"><ref id=\"nosuchbsdf\"/></shape>\n", 7, "nosuchbsdf"},
        {"undefined_variable", "    <shape type=\"sphere\"><float name=\"radius\" value=\"$nosuchvar\"/></shape>\n", 7,
         "nosuchvar"},
        {"truncated_xml", "    <shape type=\"sphere\">\n        <float name=\"radius\" value=\"1\"/>\n", 0, ""},
        {"unknown_define", "", 0, "nosuchdefine", {"-D", "nosuchdefine=3"}},
        {"negative_sigma_t",
         "    <medium type=\"homogeneous\" id=\"m\">\n        <rgb name=\"sigma_t\" value=\"1, -1, 1\"/>\n    </medium>\n",
         8, "sigma_t"},
        {"non_finite_albedo",
         "    <medium type=\"homogeneous\" id=\"m\">\n        <float name=\"albedo\" value=\"nan\"/>\n    </medium>\n",
         8, "albedo"},
        {"hg_g_out_of_range",
         "    <medium type=\"homogeneous\" id=\"m\">\n        <phase type=\"hg\"><float name=\"g\" value=\"-1\"/></phase>\n"
         "    </medium>\n",
         8, "g"},
        {"missing_grid_file",
         "    <medium type=\"heterogeneous\" id=\"m\">\n        <volume type=\"gridvolume\" name=\"sigma_t\">\n"
         "            <string name=\"filename\" value=\"nowhere.vol\"/>\n        </volume>\n    </medium>\n",
         9, "nowhere.vol"},
        {"undefined_medium", "    <shape type=\"sphere\">\n        <ref name=\"interior\" id=\"fog\"/>\n    </shape>\n", 8,
         "fog"},
        {"unknown_tag", "    <shap type=\"sphere\"/>\n", 7, "shap"},
        {"cyclic_include", "    <include filename=\"a.xml\"/>\n", 2, "a.xml", {}, "b.xml"},
        // ptracer's light paths never enter a medium: a scene with one is refused at the integrator.
        {"ptracer_with_media",
         "    <integrator type=\"ptracer\"/>\n    <medium type=\"homogeneous\" id=\"fog\"/>\n"
         "    <shape type=\"sphere\">\n        <ref name=\"interior\" id=\"fog\"/>\n    </shape>\n",
         7, "ptracer renders surfaces only"},
    };
}

// Readable test parameter names in failure messages.
void PrintTo(const BadScene& c, std::ostream* os) { *os << c.name; }

}  // namespace

class BadSceneTest : public ::testing::TestWithParam<BadScene> {};

TEST_P(BadSceneTest, ExitsOneWithFileLineAndNoOutput) {
    const BadScene& c = GetParam();
    TempDir dir(std::string("bad-") + c.name);
    std::string xml = kHeader + c.body;
    if (std::string(c.name) != "truncated_xml") xml += "</scene>\n";
    std::string scene = dir.write("scene.xml", xml);
    dir.write("a.xml", "<scene version=\"3.0.0\">\n    <include filename=\"b.xml\"/>\n</scene>\n");
    dir.write("b.xml", "<scene version=\"3.0.0\">\n<include filename=\"a.xml\"/>\n</scene>\n");
    // An existing output must survive a failed render untouched.
    std::string out = dir.write("out.exr", "sentinel");
    std::vector<std::string> args = {"render", scene, "-o", out, "--quiet"};
    args.insert(args.end(), c.extra_args.begin(), c.extra_args.end());
    CliResult r = run_cli(args);

    EXPECT_EQ(r.exit_code, 1) << r.err;
    // Exactly one line on stderr.
    ASSERT_FALSE(r.err.empty());
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    std::string pattern = c.line > 0 ? std::string("^volguide: .*") + c.file + ":" + std::to_string(c.line) + ": .+\n$"
                                     : std::string("^volguide: .*") + c.file + "(:[0-9]+)?: .+\n$";
    EXPECT_TRUE(std::regex_search(r.err, std::regex(pattern))) << "stderr: " << r.err << "expected: " << pattern;
    EXPECT_NE(r.err.find(c.fragment), std::string::npos) << r.err;
    EXPECT_EQ(read_file(out), "sentinel");
    EXPECT_FALSE(fs::exists(dir.file("out_var.exr")));
    EXPECT_FALSE(fs::exists(dir.file("scene.exr")));
}

INSTANTIATE_TEST_SUITE_P(Cli, BadSceneTest, ::testing::ValuesIn(bad_scenes()),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(CliUsage, BadCommandLinesExitTwo) {
    TempDir dir("usage");
    std::string scene = dir.write("scene.xml", kHeader + "</scene>\n");
    for (std::vector<std::string> args : std::vector<std::vector<std::string>>{
             {},
             {"frobnicate"},
             {"render"},
             {"render", scene, "--spp", "-3"},
             {"render", scene, "--spp", "many"},
             {"render", scene, "--no-such-flag"},
             {"render", scene, "-o", dir.file("out.tiff")},
         }) {
        CliResult r = run_cli(args);
        std::string joined;
        for (auto& a : args) joined += a + " ";
        EXPECT_EQ(r.exit_code, 2) << joined << "\n" << r.err;
        EXPECT_FALSE(fs::exists(dir.file("out.tiff")));
    }
}

TEST(CliUsage, MissingSceneFileExitsOne) {
    TempDir dir("missing");
    CliResult r = run_cli({"render", dir.file("nope.xml"), "-o", dir.file("x.exr")});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(std::regex_search(r.err, std::regex("^volguide: .*nope\\.xml: .+\n$"))) << r.err;
    EXPECT_FALSE(fs::exists(dir.file("x.exr")));
}
