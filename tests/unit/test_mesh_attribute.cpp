// Mesh attributes (issue 40): PLY properties grouped by Mitsuba 3's naming into vertex_*/face_*
// attributes, their values at a hit (per-vertex: barycentric interpolation; per-face: constant), the
// `mesh_attribute` texture's parameter errors, and the loader's refusal of a texture naming an
// attribute the shape lacks or used outside a BSDF (file:line of the texture / the reference).
#include <gtest/gtest.h>

#include "support/cli.h"
#include "test_loader_util.h"
#include "test_shape_util.h"
#include "volguide/render/texture.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// One quad (two triangles after the split) with per-vertex colour_0..2, a two-channel foo_x/foo_y
// (ignored: only 1 or 3 channels are attributes), and per-face weight_0 and r g b.
const char* kMeshAttrPly =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "property float color_0\nproperty float color_1\nproperty float color_2\n"
    "property float foo_x\nproperty float foo_y\n"
    "element face 1\nproperty list uchar int vertex_indices\nproperty float weight_0\n"
    "property uchar r\nproperty uchar g\nproperty uchar b\nend_header\n"
    "0 0 0  1 0 0  5 5\n1 0 0  0 1 0  5 5\n1 1 0  0 0 1  5 5\n0 1 0  1 1 1  5 5\n"
    "4 0 1 2 3  0.25  1 2 3\n";

const MeshAttribute* mesh_attr_find(const TriangleMesh& m, const std::string& name) {
    for (const MeshAttribute& a : m.attributes)
        if (a.name == name) return &a;
    return nullptr;
}

std::shared_ptr<Shape> mesh_attr_quad(const TempDir& dir) {
    return make_shape(ShapeProps("ply").s("filename", dir.write("attr.ply", kMeshAttrPly)));
}

}  // namespace

TEST(MeshAttribute, PlyPropertiesGroupedAsMitsuba) {
    TempDir dir("mesh-attr");
    auto s = mesh_attr_quad(dir);
    const TriangleMesh& m = *s->triangle_mesh();
    ASSERT_EQ(m.attributes.size(), 3u);
    const MeshAttribute* vc = mesh_attr_find(m, "vertex_color");
    ASSERT_NE(vc, nullptr);
    EXPECT_EQ(vc->channels, 3);
    EXPECT_EQ(vc->values, (std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}));
    const MeshAttribute* fw = mesh_attr_find(m, "face_weight");
    ASSERT_NE(fw, nullptr);
    EXPECT_EQ(fw->values, (std::vector<float>{0.25f, 0.25f}));  // the quad's two triangles
    const MeshAttribute* fc = mesh_attr_find(m, "face_color");
    ASSERT_NE(fc, nullptr);
    EXPECT_EQ(fc->values, (std::vector<float>{1, 2, 3, 1, 2, 3}));  // integers are not normalised
    EXPECT_EQ(mesh_attr_find(m, "vertex_foo"), nullptr);
    EXPECT_EQ(s->attribute_channels("face_weight"), 1);
    EXPECT_EQ(s->attribute_channels("vertex_color"), 3);
    EXPECT_EQ(s->attribute_channels("vertex_foo"), 0);
}

TEST(MeshAttribute, VertexValuesInterpolatedFaceValuesConstant) {
    TempDir dir("mesh-attr");
    auto s = mesh_attr_quad(dir);
    // Triangle 0 is (v0, v1, v2); barycentrics (b1, b2) = (0.2, 0.5).
    Ray ray(Point3f(0.7f, 0.5f, 1.f), Vec3f(0, 0, -1), Infinity);
    SurfaceInteraction si = s->compute_surface_interaction(ray, 1.f, 0, Vec2f(0.2f, 0.5f));
    Color3 c = s->eval_attribute("vertex_color", si);
    EXPECT_NEAR(c.r, 0.3f, 1e-5f);
    EXPECT_NEAR(c.g, 0.2f, 1e-5f);
    EXPECT_NEAR(c.b, 0.5f, 1e-5f);
    EXPECT_EQ(s->eval_attribute("face_weight", si), Color3(0.25f));
    EXPECT_EQ(s->eval_attribute("face_color", si), Color3(1, 2, 3));
}

TEST(MeshAttribute, TextureScalesAndRefusesBadNames) {
    TempDir dir("mesh-attr");
    auto s = mesh_attr_quad(dir);
    Properties props("texture", "mesh_attribute", {"t.xml", 4});
    props.set("name", "string", std::string("face_color"), {"t.xml", 5});
    props.set("scale", "float", 0.5, {"t.xml", 6});
    auto tex = std::dynamic_pointer_cast<Texture>(create_texture(props));
    props.check_all_used();
    Ray ray(Point3f(0.7f, 0.5f, 1.f), Vec3f(0, 0, -1), Infinity);
    SurfaceInteraction si = s->compute_surface_interaction(ray, 1.f, 1, Vec2f(0.2f, 0.5f));
    EXPECT_EQ(tex->eval(si), Color3(0.5f, 1.f, 1.5f));
    EXPECT_THROW(tex->mean(), std::invalid_argument);  // no mean, as Mitsuba

    Properties bad("texture", "mesh_attribute", {"t.xml", 4});
    bad.set("name", "string", std::string("color"), {"t.xml", 7});
    expect_input_error([&] { create_texture(bad); }, "t.xml", 7, "must start with \"vertex_\" or \"face_\"");
}

TEST(MeshAttribute, LoaderRefusesMissingAttributeAndNonBsdfUsers) {
    TempDir dir("mesh-attr");
    dir.write("attr.ply", kMeshAttrPly);
    const std::string head = "<scene version=\"3.0.0\">\n";
    const std::string missing = dir.write(
        "missing.xml", head +
                           "<texture type=\"mesh_attribute\" id=\"t\">\n  <string name=\"name\" value=\"vertex_w\"/>\n"
                           "</texture>\n<shape type=\"ply\">\n  <string name=\"filename\" value=\"attr.ply\"/>\n"
                           "  <bsdf type=\"diffuse\"><ref name=\"reflectance\" id=\"t\"/></bsdf>\n</shape>\n</scene>\n");
    expect_input_error([&] { load_scene_properties(missing, {}); }, missing, 2, "has no attribute \"vertex_w\"");
    const std::string present = dir.write(
        "present.xml",
        head + "<shape type=\"ply\">\n  <string name=\"filename\" value=\"attr.ply\"/>\n"
               "  <bsdf type=\"blendbsdf\">\n    <texture type=\"mesh_attribute\" name=\"weight\">\n"
               "      <string name=\"name\" value=\"face_weight\"/>\n    </texture>\n"
               "    <bsdf type=\"diffuse\"/>\n    <bsdf type=\"conductor\"/>\n  </bsdf>\n</shape>\n</scene>\n");
    EXPECT_NO_THROW(load_scene_properties(present, {}));
    const std::string emitter = dir.write(
        "emitter.xml",
        head + "<texture type=\"mesh_attribute\" id=\"t\">\n  <string name=\"name\" value=\"face_color\"/>\n"
               "</texture>\n<shape type=\"ply\">\n  <string name=\"filename\" value=\"attr.ply\"/>\n"
               "  <emitter type=\"area\"><ref name=\"radiance\" id=\"t\"/></emitter>\n</shape>\n</scene>\n");
    expect_input_error([&] { load_scene_properties(emitter, {}); }, emitter, 7, "only be used by BSDFs");
}
