// OBJ loading: quads (fan split), shared vertices, normals (given, computed, face_normals),
// uvs and flip_tex_coords, to_world, relative paths, errors; Mitsuba's test meshes.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/test_support.h"
#include "support/cli.h"
#include "test_shape_util.h"
#include "volguide/core/error.h"

using namespace volguide;
using namespace volguide::test;

namespace {

const char* kQuadObj = R"(# unit quad in z=0, as one polygon
v -1 -1 0
v 1 -1 0
v 1 1 0
v -1 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
f 1/1/1 2/2/1 3/3/1 4/4/1
)";

const TriangleMesh& obj_mesh_of(const std::shared_ptr<Shape>& s) {
    const TriangleMesh* m = s->triangle_mesh();
    EXPECT_NE(m, nullptr);
    return *m;
}

}  // namespace

TEST(MeshObj, QuadIsFanSplitWithUvsAndNormals) {
    TempDir dir("geom");
    auto s = make_shape(ShapeProps("obj").s("filename", dir.write("quad.obj", kQuadObj)));
    const TriangleMesh& m = obj_mesh_of(s);
    ASSERT_EQ(m.triangle_count(), 2u);
    EXPECT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
    ASSERT_EQ(m.normals.size(), 4u);
    ASSERT_EQ(m.uvs.size(), 4u);
    // flip_tex_coords (default true): v -> 1 - v
    EXPECT_EQ(m.uvs[0], Vec2f(0, 1));
    EXPECT_EQ(m.uvs[2], Vec2f(1, 0));
    EXPECT_NEAR(s->surface_area(), 4.f, 1e-6f);

    // Hit at (0.5, -0.5): uv interpolated from the (flipped) vertex uvs.
    SurfaceInteraction si = s->compute_surface_interaction(Ray({0.5f, -0.5f, 1}, {0, 0, -1}), 1.f, 0,
                                                           {0.5f, 0.25f});  // b0=.25,b1=.5,b2=.25
    EXPECT_NEAR(si.p.x, 0.5f, 1e-6f);
    EXPECT_NEAR(si.p.y, -0.5f, 1e-6f);
    EXPECT_NEAR(si.uv.x, 0.75f, 1e-6f);
    EXPECT_NEAR(si.uv.y, 0.75f, 1e-6f);
    EXPECT_NEAR(si.n.z, 1.f, 1e-6f);
    EXPECT_NEAR(si.wi.z, 1.f, 1e-6f);
    // dp_du is +x (u grows with x); dp_dv is -y because of the flip.
    EXPECT_NEAR(si.sh_frame.s.x, 1.f, 1e-6f);
    EXPECT_NEAR(si.dp_dv.y, -2.f, 1e-5f);
}

TEST(MeshObj, FlipTexCoordsFalse) {
    TempDir dir("geom");
    auto s = make_shape(
        ShapeProps("obj").s("filename", dir.write("quad.obj", kQuadObj)).b("flip_tex_coords", false));
    EXPECT_EQ(obj_mesh_of(s).uvs[0], Vec2f(0, 0));
}

TEST(MeshObj, ComputesSmoothNormalsUnlessFaceNormals) {
    TempDir dir("geom");
    // Two triangles folded along the y axis: the shared edge gets the averaged normal.
    std::string file = dir.write("fold.obj", "v 0 0 0\nv 0 1 0\nv 1 0 1\nv -1 0 1\nf 1 3 2\nf 1 2 4\n");
    auto smooth = make_shape(ShapeProps("obj").s("filename", file));
    const TriangleMesh& m = obj_mesh_of(smooth);
    ASSERT_EQ(m.normals.size(), 4u);
    EXPECT_NEAR(m.normals[0].x, 0.f, 1e-6f);
    EXPECT_NEAR(m.normals[0].z, 1.f, 1e-6f);
    EXPECT_TRUE(m.uvs.empty());

    auto faceted = make_shape(ShapeProps("obj").s("filename", file).b("face_normals", true));
    EXPECT_TRUE(obj_mesh_of(faceted).normals.empty());
    // Shading normal = geometric normal; uv = barycentrics (b1, b2).
    SurfaceInteraction si =
        faceted->compute_surface_interaction(Ray({0.2f, 0.2f, 1}, {0, 0, -1}), 1.f, 0, {0.3f, 0.2f});
    EXPECT_EQ(si.sh_frame.n, si.n);
    EXPECT_EQ(si.uv, Vec2f(0.3f, 0.2f));
}

TEST(MeshObj, ToWorldAndFlipNormals) {
    TempDir dir("geom");
    auto s =
        make_shape(ShapeProps("obj")
                       .s("filename", dir.write("quad.obj", kQuadObj))
                       .t("to_world", Transform::translate({0, 0, 3}) * Transform::rotate({1, 0, 0}, 90.f))
                       .b("flip_normals", true));
    const TriangleMesh& m = obj_mesh_of(s);
    EXPECT_NEAR(m.positions[0].z, 3.f - 1.f, 1e-5f);  // (-1,-1,0) -> (-1,0,-1) + (0,0,3)
    EXPECT_NEAR(m.normals[0].y, -1.f, 1e-5f);         // +z rotated to -y (stored normals are not flipped)
    SurfaceInteraction si = s->compute_surface_interaction(Ray({0, 5, 3}, {0, -1, 0}), 5.f, 0, {0.3f, 0.3f});
    EXPECT_NEAR(si.n.y, 1.f, 1e-5f);  // flipped
    EXPECT_NEAR(si.sh_frame.n.y, 1.f, 1e-5f);
    PositionSample ps = s->sample_position({0.3f, 0.6f});
    EXPECT_NEAR(ps.n.y, 1.f, 1e-5f);
    EXPECT_NEAR(ps.pdf, 0.25f, 1e-6f);
}

TEST(MeshObj, RelativeToSceneFile) {
    TempDir dir("geom");
    dir.write("quad.obj", kQuadObj);
    std::string scene = (dir.path() / "scene.xml").string();
    ShapeProps sp("obj", scene);
    sp.props.set("filename", "string", std::string("quad.obj"), SourceLocation{scene, 3});
    EXPECT_EQ(obj_mesh_of(make_shape(sp)).triangle_count(), 2u);
}

TEST(MeshObj, Errors) {
    TempDir dir("geom");
    try {
        make_shape(ShapeProps("obj").s("filename", (dir.path() / "missing.obj").string()));
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("missing.obj"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("not found"), std::string::npos);
    }
    EXPECT_THROW(
        make_shape(ShapeProps("obj").s("filename", dir.write("bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n"))),
        InputError);
    EXPECT_THROW(make_shape(ShapeProps("obj").s("filename", dir.write("empty.obj", "v 0 0 0\n"))),
                 InputError);
}

TEST(MeshObj, MitsubaTestMeshes) {
    namespace fs = std::filesystem;
    fs::path dir = fs::path(shared_dir()) / "mitsuba-data/tests/scenes/participating_media/meshes";
    if (!fs::exists(dir)) GTEST_SKIP() << "Mitsuba test data not found at " << dir;
    int loaded = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.path().extension() != ".obj") continue;
        SCOPED_TRACE(entry.path().string());
        auto s = make_shape(ShapeProps("obj").s("filename", entry.path().string()));
        const TriangleMesh& m = obj_mesh_of(s);
        EXPECT_GT(m.triangle_count(), 0u);
        EXPECT_EQ(m.normals.size(), m.positions.size());
        EXPECT_GT(s->surface_area(), 0.f);
        ++loaded;
    }
    EXPECT_GT(loaded, 0);
    // unit_cube_centered.obj: the cube [-0.5, 0.5]^3 (area 6).
    fs::path cube = dir / "unit_cube_centered.obj";
    if (fs::exists(cube)) {
        auto s = make_shape(ShapeProps("obj").s("filename", cube.string()));
        EXPECT_NEAR(s->surface_area(), 6.f, 1e-4f);
        EXPECT_NEAR(s->bbox().hi.x, 0.5f, 1e-6f);
    }
}
