// Malformed scenes: each must be an InputError naming the right file and line.
#include <gtest/gtest.h>

#include <filesystem>

#include "test_loader_util.h"

using namespace volguide;
using namespace volguide::test;
namespace fs = std::filesystem;

namespace {

struct BadScene {
    const char* what;
    std::string xml;  // whole file
    int line;
    const char* needle;
};

// Line 1 is <scene version="3.0.0">, so the body starts at line 2.
const std::vector<BadScene> kBadScenes = {
    {"unknown tag", scene("<bsdf type=\"diffuse\"/>\n<bdsf type=\"diffuse\"/>\n"), 3,
     "unknown element <bdsf>"},
    {"unknown attribute", scene("<bsdf type=\"diffuse\">\n  <float name=\"a\" valeu=\"1\"/>\n</bsdf>\n"), 3,
     "unexpected attribute 'valeu'"},
    {"missing type", scene("\n<bsdf id=\"x\"/>\n"), 3, "'type'"},
    {"missing name", scene("<bsdf type=\"d\">\n  <float value=\"1\"/>\n</bsdf>\n"), 3, "'name'"},
    {"missing value", scene("<bsdf type=\"d\">\n  <integer name=\"n\"/>\n</bsdf>\n"), 3, "'value'"},
    {"bad float", scene("<bsdf type=\"d\">\n\n  <float name=\"a\" value=\"1.0x\"/>\n</bsdf>\n"), 4, "1.0x"},
    {"nan in rgb", scene("<bsdf type=\"d\">\n  <rgb name=\"a\" value=\"0.5, nan, 1\"/>\n</bsdf>\n"), 3,
     "nan"},
    {"bad integer", scene("<film type=\"hdrfilm\">\n  <integer name=\"width\" value=\"12.5\"/>\n</film>\n"),
     3, "12.5"},
    {"bad boolean", scene("<bsdf type=\"d\">\n  <boolean name=\"b\" value=\"yes\"/>\n</bsdf>\n"), 3, "yes"},
    {"mismatched closing tag", scene("<bsdf type=\"d\">\n  <float name=\"a\" value=\"1\"/>\n</shape>\n"), 4,
     "malformed XML"},
    {"unterminated attribute", "<scene version=\"3.0.0\">\n<bsdf type=\"d>\n</bsdf>\n</scene>\n", 2,
     "malformed XML"},
    {"truncated file", "<scene version=\"3.0.0\">\n<bsdf type=\"d\">\n  <float name=\"a\" value=\"1\"/>\n", 3,
     "malformed XML"},
    {"transform op outside transform", scene("<shape type=\"s\">\n  <translate x=\"1\"/>\n</shape>\n"), 3,
     "only appear inside <transform>"},
    {"value inside transform",
     scene("<shape type=\"s\">\n <transform name=\"to_world\">\n  <float name=\"x\" value=\"1\"/>\n"
           " </transform>\n</shape>\n"),
     4, "cannot appear inside <transform>"},
    {"rotate without angle",
     scene("<shape type=\"s\">\n <transform name=\"t\">\n  <rotate x=\"1\"/>\n </transform>\n</shape>\n"), 4,
     "'angle'"},
    {"matrix with 15 values",
     scene(
         "<shape type=\"s\">\n <transform name=\"t\">\n  <matrix value=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0\"/>\n"
         " </transform>\n</shape>\n"),
     4, "16"},
    {"singular matrix",
     scene("<shape type=\"s\">\n <transform name=\"t\">\n  <matrix value=\"1 0 0 0 0 0 0 0 0 0 1 0 0 0 0 "
           "1\"/>\n"
           " </transform>\n</shape>\n"),
     4, "singular"},
    {"lookat with coincident points",
     scene("<sensor type=\"p\">\n <transform name=\"t\">\n  <lookat origin=\"1 2 3\" target=\"1 2 3\"/>\n"
           " </transform>\n</sensor>\n"),
     4, "lookat"},
    {"unused parameter",
     scene("<bsdf type=\"strict\">\n  <float name=\"roughnes\" value=\"0.1\"/>\n</bsdf>\n"), 3, "roughnes"},
    {"duplicate parameter",
     scene("<bsdf type=\"d\">\n  <float name=\"a\" value=\"1\"/>\n  <float name=\"a\" "
           "value=\"2\"/>\n</bsdf>\n"),
     4, "twice"},
    {"text inside an object", scene("<bsdf type=\"d\">\n  oops\n</bsdf>\n"), 3, "unexpected text"},
    {"decreasing spectrum",
     scene("<bsdf type=\"d\">\n  <spectrum name=\"r\" value=\"500:1, 400:1\"/>\n</bsdf>\n"), 3, "increasing"},
    {"root is not a scene", "<bsdf version=\"3.0.0\" type=\"d\"/>\n", 1, "<scene>"},
    {"missing version", "\n<scene>\n</scene>\n", 2, "'version'"},
    // 0.4 to 0.6 are read since issue 50 (test_loader_legacy.cpp); older and unknown versions are not.
    {"old version", "<scene version=\"0.3.0\">\n</scene>\n", 1, "predates Mitsuba 0.4"},
    {"unknown version", "<scene version=\"1.0.0\">\n</scene>\n", 1, "not supported"},
    {"nested scene", scene("<shape type=\"s\">\n  <scene version=\"3.0.0\"/>\n</shape>\n"), 3,
     "root element"},
    {"path not at top level", scene("<shape type=\"s\">\n  <path value=\".\"/>\n</shape>\n"), 3, "<path>"},
    {"include not found", scene("\n<include filename=\"nothere.xml\"/>\n"), 3, "nothere.xml"},
    {"missing path directory", scene("<path value=\"no/such/dir\"/>\n"), 2, "no/such/dir"},
    {"reserved name", scene("<bsdf type=\"d\">\n  <float name=\"_x\" value=\"1\"/>\n</bsdf>\n"), 3,
     "reserved"},
};

}  // namespace

TEST(LoaderErrors, EachMalformedSceneReportsFileAndLine) {
    ScratchDir dir;
    for (size_t i = 0; i < kBadScenes.size(); ++i) {
        const BadScene& bad = kBadScenes[i];
        SCOPED_TRACE(bad.what);
        std::string path = dir.write("bad" + std::to_string(i) + ".xml", bad.xml);
        expect_input_error([&] { load_fake(path); }, path, bad.line, bad.needle);
    }
}

TEST(LoaderErrors, ErrorInsideAnIncludedFileNamesThatFile) {
    ScratchDir dir;
    std::string main = dir.write("main.xml", scene("<include filename=\"sub/part.xml\"/>\n"));
    dir.write("sub/part.xml",
              "<scene version=\"3.0.0\">\n  <bsdf type=\"d\">\n    <float name=\"a\" value=\"x\"/>\n"
              "  </bsdf>\n</scene>\n");
    // Spelled relative to the main file as the user gave it.
    std::string expected = (fs::path(main).parent_path() / "sub/part.xml").string();
    expect_input_error([&] { load_fake(main); }, expected, 3, "\"x\"");
}

TEST(LoaderErrors, MissingSceneFile) {
    ScratchDir dir;
    std::string path = dir.path("absent.xml");
    expect_input_error([&] { load_fake(path); }, path, 0, "not found");
}

TEST(LoaderErrors, RelativeScenePathIsKeptInMessages) {
    ScratchDir dir;
    dir.write("scenes/s.xml", scene("<bsdf type=\"d\">\n  <float name=\"a\" value=\"oops\"/>\n</bsdf>\n"));
    fs::path old = fs::current_path();
    fs::current_path(dir.path());
    expect_input_error([&] { load_fake("scenes/s.xml"); }, "scenes/s.xml", 3, "oops");
    fs::current_path(old);
}

TEST(LoaderErrors, MediumReferencedButNeverDefined) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene("<shape type=\"sphere\">\n  <ref name=\"interior\" id=\"fog\"/>\n"
                                                "</shape>\n"));
    // The real factory table: media are supported, an undefined id is still an error at the ref.
    expect_input_error([&] { load_scene_properties(path, {}, create_object); }, path, 3, "fog");
}

TEST(LoaderErrors, ReferenceCycle) {
    ScratchDir dir;
    std::string path =
        dir.write("s.xml", scene("<texture type=\"a\" id=\"a\">\n  <ref id=\"b\"/>\n</texture>\n"
                                 "<texture type=\"b\" id=\"b\">\n  <ref id=\"a\"/>\n</texture>\n"));
    expect_input_error([&] { load_fake(path); }, path, 6, "cycle");
}

TEST(LoaderErrors, PluginExceptionsGetTheObjectsLocation) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene("\n<shape type=\"obj\"/>\n"));
    expect_input_error(
        [&] {
            load_scene_properties(path, {}, [](const std::string&, const Properties&) -> ObjectPtr {
                throw std::runtime_error("mesh has no faces");
            });
        },
        path, 3, "mesh has no faces");
}
