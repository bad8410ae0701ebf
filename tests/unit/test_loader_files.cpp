// Defaults, -D, includes, <path>, file parameters, ids and references.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/test_support.h"
#include "test_loader_util.h"

using namespace volguide;
using namespace volguide::test;
namespace fs = std::filesystem;

TEST(LoaderDefaults, SubstitutesEverywhereIncludingPartialStrings) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene(R"(<default name="res" value="64"/>
<default name="kind" value="diffuse"/>
<bsdf type="$kind">
  <integer name="width" value="$res"/>
  <string name="label" value="img_${res}"/>
  <string name="label2" value="img_$res.exr"/>
</bsdf>
)"));
    // "${res}" is not Mitsuba syntax: '$' followed by '{' is an undefined parameter.
    expect_input_error([&] { load_fake(path); }, path, 6, "$");
    std::string ok = dir.write("t.xml", scene(R"(<default name="res" value="64"/>
<default name="kind" value="diffuse"/>
<bsdf type="$kind">
  <integer name="width" value="$res"/>
  <string name="label" value="img_$res.exr"/>
</bsdf>
)"));
    Properties b = child(load_fake(ok), "bsdf")->props;
    EXPECT_EQ(b.type(), "diffuse");
    EXPECT_EQ(b.get_int("width"), 64);
    EXPECT_EQ(b.get_string("label"), "img_64.exr");
}

TEST(LoaderDefaults, DefaultAfterUseAndInsideAnInclude) {
    ScratchDir dir;
    dir.write("inc/params.xml",
              "<scene version=\"2.0.0\">\n  <default name=\"spp\" value=\"16\"/>\n</scene>\n");
    std::string path = dir.write("s.xml", scene(R"(<sampler type="independent">
  <integer name="sample_count" value="$spp"/>
  <integer name="seed" value="$seed"/>
</sampler>
<default name="seed" value="7"/>
<include filename="inc/params.xml"/>
)"));
    Properties s = child(load_fake(path), "sampler")->props;
    EXPECT_EQ(s.get_int("sample_count"), 16);
    EXPECT_EQ(s.get_int("seed"), 7);

    LoadOptions options;
    options.defines = {{"spp", "1024"}, {"seed", "3"}};
    Properties o = child(load_fake(path, options), "sampler")->props;
    EXPECT_EQ(o.get_int("sample_count"), 1024);
    EXPECT_EQ(o.get_int("seed"), 3);
}

TEST(LoaderDefaults, UnknownDefineAndUndefinedParameter) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene("<default name=\"spp\" value=\"4\"/>\n"));
    LoadOptions options;
    options.defines = {{"sp", "8"}};
    expect_input_error([&] { load_fake(path, options); }, path, 0, "sp");
    std::string undefined =
        dir.write("u.xml", scene("<bsdf type=\"diffuse\">\n<float name=\"a\" value=\"$alpha\"/>\n</bsdf>\n"));
    expect_input_error([&] { load_fake(undefined); }, undefined, 3, "$alpha");
}

TEST(LoaderFiles, IncludeRelativeToTheIncludingFileWithPathAndFilenameResolution) {
    ScratchDir dir;
    dir.write("meshes/a.obj", "o a\n");
    dir.write("assets/tex/wood.png", "not really a png");
    dir.write("parts/local.obj", "o local\n");
    dir.write("parts/shapes.xml", R"(<scene version="3.0.0">
  <shape type="obj">
    <string name="filename" value="local.obj"/>
  </shape>
  <include filename="more.xml"/>
</scene>
)");
    dir.write("parts/more.xml", R"(<shape version="3.0.0" type="obj" id="more">
  <string name="filename" value="meshes/a.obj"/>
</shape>
)");
    std::string path = dir.write("main.xml", scene(R"(<path value="assets"/>
<include filename="parts/shapes.xml"/>
<texture type="bitmap" id="wood">
  <string name="filename" value="tex/wood.png"/>
</texture>
)"));
    Properties root = load_fake(path);
    ASSERT_EQ(root.children("shape").size(), 2u);
    auto local = child(root, "shape", 0);
    EXPECT_EQ(fs::path(local->props.get_string("filename")), fs::path(dir.path("parts/local.obj")));
    EXPECT_TRUE(fs::path(local->props.get_string("filename")).is_absolute());
    EXPECT_EQ(local->props.location().file, (fs::path(dir.path()) / "parts/shapes.xml").string());
    EXPECT_EQ(local->props.location().line, 2);
    // Not next to parts/more.xml: found through the main scene directory.
    auto more = child(root, "shape", 1);
    EXPECT_EQ(fs::path(more->props.get_string("filename")), fs::path(dir.path("meshes/a.obj")));
    EXPECT_EQ(more->props.id(), "more");
    // Through <path>.
    auto wood = child(root, "texture");
    EXPECT_EQ(fs::path(wood->props.get_string("filename")), fs::path(dir.path("assets/tex/wood.png")));
}

TEST(LoaderFiles, MissingFileIsReportedAtItsLine) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene(R"(<shape type="obj">
  <string name="filename" value="nowhere.obj"/>
</shape>
)"));
    expect_input_error([&] { load_fake(path); }, path, 3, "nowhere.obj");
}

TEST(LoaderFiles, CyclicIncludeNamesTheCycle) {
    ScratchDir dir;
    dir.write("a.xml", "<scene version=\"3.0.0\">\n  <include filename=\"b.xml\"/>\n</scene>\n");
    dir.write("b.xml", "<scene version=\"3.0.0\">\n\n  <include filename=\"a.xml\"/>\n</scene>\n");
    std::string path = dir.path("a.xml");
    std::string b = (fs::path(dir.path()) / "b.xml").string();
    try {
        load_fake(path);
        FAIL() << "cycle not detected";
    } catch (const InputError& e) {
        EXPECT_EQ(e.location().file, b);
        EXPECT_EQ(e.location().line, 3);
        EXPECT_NE(e.message().find("cyclic include"), std::string::npos) << e.what();
        EXPECT_NE(e.message().find("a.xml -> "), std::string::npos) << e.what();
    }
}

TEST(LoaderFiles, IncludingTheSameFileTwiceIsFine) {
    ScratchDir dir;
    dir.write("common.xml", "<scene version=\"3.0.0\">\n  <default name=\"x\" value=\"1\"/>\n</scene>\n");
    dir.write("a.xml", "<scene version=\"3.0.0\">\n  <include filename=\"common.xml\"/>\n</scene>\n");
    std::string path =
        dir.write("s.xml", scene("<include filename=\"a.xml\"/>\n<include filename=\"common.xml\"/>\n"));
    EXPECT_NO_THROW(load_fake(path));
}

TEST(LoaderRefs, SharedInstancesAndNamedReferences) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene(R"(<shape type="sphere">
  <ref id="white"/>
  <ref id="white" name="other"/>
</shape>
<bsdf type="diffuse" id="white"/>
<shape type="cube"><ref id="white"/></shape>
)"));
    int created = 0;
    auto counting = [&](const std::string& tag, const Properties& props) {
        if (tag == "bsdf") ++created;
        return fake_factory(tag, props);
    };
    Properties root = load_scene_properties(path, {}, counting);
    EXPECT_EQ(created, 1);  // defined once, used three times
    auto sphere = child(root, "shape", 0);
    auto cube = child(root, "shape", 1);
    ASSERT_EQ(sphere->props.children("bsdf").size(), 2u);
    ObjectPtr a = std::get<ObjectPtr>(sphere->props.children("bsdf")[0]->value);
    ObjectPtr b = sphere->props.get_object("other");
    ObjectPtr c = std::get<ObjectPtr>(cube->props.children("bsdf")[0]->value);
    ObjectPtr top = std::get<ObjectPtr>(root.children("bsdf")[0]->value);
    EXPECT_EQ(a, b);
    EXPECT_EQ(a, c);
    EXPECT_EQ(a, top);
    EXPECT_EQ(sphere->props.find("other")->loc.line, 4);
}

TEST(LoaderRefs, UnknownAndDuplicateIds) {
    ScratchDir dir;
    std::string unknown =
        dir.write("u.xml", scene("<shape type=\"sphere\">\n  <ref id=\"nope\"/>\n</shape>\n"));
    expect_input_error([&] { load_fake(unknown); }, unknown, 3, "nope");
    std::string dup = dir.write(
        "d.xml", scene("<bsdf type=\"diffuse\" id=\"x\"/>\n\n<bsdf type=\"conductor\" id=\"x\"/>\n"));
    expect_input_error([&] { load_fake(dup); }, dup, 4, "duplicate id \"x\"");
}

TEST(LoaderRefs, Alias) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene(R"(<bsdf type="diffuse" id="a"/>
<alias id="a" as="b"/>
<shape type="sphere"><ref id="b" name="bsdf"/></shape>
)"));
    Properties root = load_fake(path);
    EXPECT_EQ(child(root, "shape")->props.get_object("bsdf"),
              std::get<ObjectPtr>(root.children("bsdf")[0]->value));
}

TEST(LoaderFiles, MitsubaMediaTestSceneStructure) {
    // One of Mitsuba 3's own test scenes: <path> to ../../../common, a nested include that is
    // resolved against the main scene directory, defaults from an included preamble, $integrator.
    fs::path scene_path = fs::path(shared_dir()) / "mitsuba-data/tests/scenes/participating_media" /
                          "test_homo_emitter_inside_medium_volpath.xml";
    if (!fs::exists(scene_path)) GTEST_SKIP() << "mitsuba-data not available";
    LoadOptions options;
    options.defines = {{"spp", "4"}};
    Properties root = load_fake(scene_path.string(), options);
    auto moment = child(root, "integrator");
    ASSERT_TRUE(moment);
    EXPECT_EQ(moment->props.type(), "moment");
    EXPECT_EQ(child(moment->props, "integrator")->props.type(), "volpath");
    auto sensor = child(root, "sensor");
    EXPECT_EQ(child(sensor->props, "sampler")->props.get_int("sample_count"), 4);
    EXPECT_EQ(child(sensor->props, "film")->props.get_int("width"), 48);
    auto env = child(root, "emitter");
    EXPECT_TRUE(fs::exists(env->props.get_string("filename")));
    EXPECT_EQ(root.children("medium").size(), 1u);
    EXPECT_EQ(root.children("shape").size(), 5u);  // 1 from the base include + 4 here
}

TEST(LoaderFiles, AllMitsubaMediaTestScenesParse) {
    fs::path dir = fs::path(shared_dir()) / "mitsuba-data/tests/scenes/participating_media";
    if (!fs::exists(dir)) GTEST_SKIP() << "mitsuba-data not available";
    int n = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.path().extension() != ".xml") continue;
        SCOPED_TRACE(entry.path().string());
        EXPECT_NO_THROW({
            try {
                load_fake(entry.path().string());
            } catch (const InputError& e) {
                ADD_FAILURE() << e.what();
                throw;
            }
        });
        ++n;
    }
    EXPECT_EQ(n, 12);
}
