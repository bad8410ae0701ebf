// Value parameters and transforms as the loader hands them to plugin factories.
#include <gtest/gtest.h>

#include <cmath>

#include "test_loader_util.h"

using namespace volguide;
using namespace volguide::test;

namespace {

Properties one_bsdf(const ScratchDir& dir, const std::string& params) {
    std::string path = dir.write("s.xml", scene("<bsdf type=\"diffuse\">\n" + params + "</bsdf>\n"));
    Properties root = load_fake(path);
    auto b = child(root, "bsdf");
    if (!b) throw std::runtime_error("no bsdf");
    return b->props;
}

void expect_matrix_near(const Matrix4& a, const Matrix4& b, double tol = 1e-6) {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_NEAR(a.m[i][j], b.m[i][j], tol) << "entry " << i << "," << j;
}

}  // namespace

TEST(LoaderProperties, ScalarTypes) {
    ScratchDir dir;
    Properties p = one_bsdf(dir,
                            "<integer name=\"i\" value=\"-42\"/>\n"
                            "<float name=\"f\" value=\"2.5e-1\"/>\n"
                            "<float name=\"g\" value=\"+3\"/>\n"
                            "<boolean name=\"b\" value=\"TRUE\"/>\n"
                            "<boolean name=\"c\" value=\"false\"/>\n"
                            "<string name=\"s\" value=\"hello world\"/>\n");
    EXPECT_EQ(p.category(), "bsdf");
    EXPECT_EQ(p.type(), "diffuse");
    EXPECT_EQ(p.get_int("i"), -42);
    EXPECT_FLOAT_EQ(p.get_float("f"), 0.25f);
    EXPECT_FLOAT_EQ(p.get_float("g"), 3.f);
    EXPECT_TRUE(p.get_bool("b"));
    EXPECT_FALSE(p.get_bool("c"));
    EXPECT_EQ(p.get_string("s"), "hello world");
    EXPECT_EQ(p.find("i")->loc.line, 3);
    EXPECT_EQ(p.find("s")->loc.line, 8);
}

TEST(LoaderProperties, ColorsAndVectors) {
    ScratchDir dir;
    Properties p = one_bsdf(dir,
                            "<rgb name=\"a\" value=\"0.1, 0.2 ,0.3\"/>\n"
                            "<rgb name=\"b\" value=\"0.5\"/>\n"
                            "<spectrum name=\"c\" value=\"0.25\"/>\n"
                            "<point name=\"p\" value=\"1 2 3\"/>\n"
                            "<point name=\"q\" x=\"4\" y=\"5\" z=\"6\"/>\n"
                            "<vector name=\"v\" value=\"7\"/>\n");
    EXPECT_EQ(p.get_color("a"), Color3(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(p.get_color("b"), Color3(0.5f));
    EXPECT_EQ(p.get_color("c"), Color3(0.25f));
    EXPECT_EQ(p.find("c")->category, "spectrum");
    EXPECT_EQ(p.get_vec3("p"), Vec3f(1, 2, 3));
    EXPECT_EQ(p.get_vec3("q"), Vec3f(4, 5, 6));
    EXPECT_EQ(p.get_vec3("v"), Vec3f(7, 7, 7));
    EXPECT_EQ(p.find("v")->category, "vector");
}

TEST(LoaderProperties, TransformOperations) {
    ScratchDir dir;
    Properties p = one_bsdf(
        dir,
        "<transform name=\"t1\"><translate x=\"1\" z=\"3\"/></transform>\n"
        "<transform name=\"t2\"><translate value=\"1, 2, 3\"/></transform>\n"
        "<transform name=\"s1\"><scale value=\"2\"/></transform>\n"
        "<transform name=\"s2\"><scale y=\"4\"/></transform>\n"
        "<transform name=\"r1\"><rotate y=\"1\" angle=\"90\"/></transform>\n"
        "<transform name=\"r2\"><rotate value=\"0 1 0\" angle=\"90\"/></transform>\n"
        "<transform name=\"m\"><matrix value=\"1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1\"/></transform>\n"
        "<transform name=\"m3\"><matrix value=\"0,-1,0, 1,0,0, 0,0,1\"/></transform>\n"
        "<transform name=\"l\"><lookat origin=\"0, 0.5, 4\" target=\"0 -0.5 0\" up=\"0 1 0\"/></transform>\n"
        "<transform name=\"l0\"><lookat origin=\"1 1 1\" target=\"1 1 5\"/></transform>\n");
    expect_matrix_near(p.get_transform("t1").matrix(), Transform::translate({1, 0, 3}).matrix());
    expect_matrix_near(p.get_transform("t2").matrix(), Transform::translate({1, 2, 3}).matrix());
    expect_matrix_near(p.get_transform("s1").matrix(), Transform::scale({2, 2, 2}).matrix());
    expect_matrix_near(p.get_transform("s2").matrix(), Transform::scale({1, 4, 1}).matrix());
    expect_matrix_near(p.get_transform("r1").matrix(), Transform::rotate({0, 1, 0}, 90).matrix());
    expect_matrix_near(p.get_transform("r2").matrix(), Transform::rotate({0, 1, 0}, 90).matrix());
    Point3f q = p.get_transform("m").apply_point({1, 1, 1});
    EXPECT_EQ(q, Point3f(6, 7, 8));
    Vec3f r = p.get_transform("m3").apply_vector({1, 0, 0});  // row-major 3x3: x → +y
    EXPECT_NEAR(r.x, 0.f, 1e-6);
    EXPECT_NEAR(r.y, 1.f, 1e-6);
    expect_matrix_near(p.get_transform("l").matrix(),
                       Transform::look_at({0, 0.5f, 4}, {0, -0.5f, 0}, {0, 1, 0}).matrix());
    // Without 'up' any perpendicular up vector is chosen; the view direction must still be right.
    Transform l0 = p.get_transform("l0");
    Vec3f fwd = l0.apply_vector({0, 0, 1});
    EXPECT_NEAR(fwd.z, 1.f, 1e-6);
    EXPECT_EQ(l0.apply_point({0, 0, 0}), Point3f(1, 1, 1));
}

TEST(LoaderProperties, LaterTransformOperationsApplyAfterEarlierOnes) {
    ScratchDir dir;
    Properties p = one_bsdf(dir,
                            "<transform name=\"t\">\n"
                            "  <scale value=\"2\"/>\n"
                            "  <rotate z=\"1\" angle=\"90\"/>\n"
                            "  <translate x=\"10\"/>\n"
                            "</transform>\n");
    Transform expected =
        Transform::translate({10, 0, 0}) * Transform::rotate({0, 0, 1}, 90) * Transform::scale({2, 2, 2});
    expect_matrix_near(p.get_transform("t").matrix(), expected.matrix());
    Point3f x = p.get_transform("t").apply_point({1, 0, 0});  // scale → (2,0,0), rotate → (0,2,0), +10
    EXPECT_NEAR(x.x, 10.f, 1e-5);
    EXPECT_NEAR(x.y, 2.f, 1e-5);
}

TEST(LoaderProperties, NestedObjectsBecomeChildEntries) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene(R"(<shape type="sphere">
  <bsdf type="diffuse" name="named"/>
  <bsdf type="conductor"/>
  <emitter type="area"><rgb name="radiance" value="1"/></emitter>
</shape>
<integrator type="path"/>
)"));
    Properties root = load_fake(path);
    EXPECT_EQ(root.category(), "scene");
    auto shape = child(root, "shape");
    ASSERT_TRUE(shape);
    EXPECT_EQ(shape->props.location().line, 2);
    ASSERT_EQ(shape->props.children("bsdf").size(), 2u);
    EXPECT_EQ(shape->props.children("bsdf")[0]->name, "named");
    EXPECT_EQ(shape->props.children("bsdf")[1]->name, "");
    auto conductor = child(shape->props, "bsdf", 1);
    EXPECT_EQ(conductor->props.type(), "conductor");
    auto emitter = child(shape->props, "emitter");
    ASSERT_TRUE(emitter);
    EXPECT_EQ(emitter->props.get_color("radiance"), Color3(1.f));
    ASSERT_TRUE(child(root, "integrator"));
    EXPECT_EQ(child(root, "integrator")->props.type(), "path");
}

TEST(LoaderProperties, ChildrenAreCreatedBeforeParents) {
    ScratchDir dir;
    std::string path =
        dir.write("s.xml", scene(R"(<shape type="a"><bsdf type="b"><texture type="c" name="t"/></bsdf></shape>
)"));
    std::vector<std::string> order;
    auto recording = [&](const std::string& tag, const Properties& props) {
        order.push_back(props.type());
        return fake_factory(tag, props);
    };
    load_scene_properties(path, {}, recording);
    EXPECT_EQ(order, (std::vector<std::string>{"c", "b", "a"}));
}

TEST(LoaderProperties, SpectrumPluginIsATexture) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene(R"(<bsdf type="diffuse">
  <spectrum type="d65" name="reflectance"/>
</bsdf>
)"));
    auto bsdf = child(load_fake(path), "bsdf");
    auto tex = child(bsdf->props, "texture");
    ASSERT_TRUE(tex);
    EXPECT_EQ(tex->tag, "texture");
    EXPECT_EQ(tex->props.type(), "d65");
}

TEST(LoaderProperties, DeclarationCommentsAndCrlfLineEndings) {
    ScratchDir dir;
    std::string path = dir.write("s.xml",
                                 "<?xml version=\"1.0\" encoding=\"utf-8\"?>\r\n"
                                 "<!-- a comment\r\n spanning lines -->\r\n"
                                 "<scene version=\"2.1.0\">\r\n"
                                 "  <!-- <bsdf type=\"commented-out\"/> -->\r\n"
                                 "  <bsdf type=\"diffuse\">\r\n"
                                 "    <float name=\"a\" value=\"1\"/>\r\n"
                                 "  </bsdf>\r\n"
                                 "</scene>\r\n");
    Properties root = load_fake(path);
    ASSERT_EQ(root.children("bsdf").size(), 1u);
    EXPECT_EQ(root.location().line, 4);
    Properties b = child(root, "bsdf")->props;
    EXPECT_EQ(b.location().line, 6);
    EXPECT_EQ(b.find("a")->loc.line, 7);
}
