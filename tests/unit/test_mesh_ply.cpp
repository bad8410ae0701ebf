// PLY reading: ascii, binary little/big endian, quads, normals, uv naming variants, extra
// elements and properties, malformed files (errors name the file).
#include <gtest/gtest.h>

#include <bit>
#include <cstring>

#include "support/cli.h"
#include "test_shape_util.h"
#include "volguide/core/error.h"

using namespace volguide;
using namespace volguide::test;

namespace {

const TriangleMesh& ply_mesh_of(const std::shared_ptr<Shape>& s) {
    return *s->triangle_mesh();
}

// Appends a value in the requested byte order.
template <typename T>
void put(std::string& out, T v, bool little) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (little != (std::endian::native == std::endian::little))
        for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

// The unit quad [-1,1]^2 at z=0 as one quad face, with normals, s/t uvs, a per-vertex extra
// property, a per-face extra list, and an unrelated element.
std::string binary_quad(bool little) {
    std::string s =
        std::string("ply\nformat ") + (little ? "binary_little_endian" : "binary_big_endian") +
        " 1.0\ncomment test\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\n"
        "property float s\nproperty float t\nelement face 1\nproperty list uchar int vertex_indices\n"
        "property list uchar float extra\nelement edge 1\nproperty int a\nproperty double b\nend_header\n";
    const float pos[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    const float uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int i = 0; i < 4; ++i) {
        put<float>(s, pos[i][0], little);
        put<float>(s, pos[i][1], little);
        put<float>(s, 0.f, little);
        put<float>(s, 0.f, little);
        put<float>(s, 0.f, little);
        put<float>(s, 1.f, little);
        put<uint8_t>(s, 200, little);
        put<float>(s, uv[i][0], little);
        put<float>(s, uv[i][1], little);
    }
    put<uint8_t>(s, 4, little);
    for (int i : {0, 1, 2, 3}) put<int32_t>(s, i, little);
    put<uint8_t>(s, 2, little);
    put<float>(s, 7.f, little);
    put<float>(s, 8.f, little);
    put<int32_t>(s, 5, little);
    put<double>(s, 6.0, little);
    return s;
}

void expect_quad(const TriangleMesh& m) {
    ASSERT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.positions[2], Vec3f(1, 1, 0));
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
    ASSERT_EQ(m.normals.size(), 4u);
    EXPECT_EQ(m.normals[3], Vec3f(0, 0, 1));
    ASSERT_EQ(m.uvs.size(), 4u);
    EXPECT_EQ(m.uvs[1], Vec2f(1, 0));  // PLY uvs are not flipped
}

}  // namespace

TEST(MeshPly, BinaryLittleEndian) {
    TempDir dir("geom");
    auto s = make_shape(ShapeProps("ply").s("filename", dir.write("le.ply", binary_quad(true))));
    expect_quad(ply_mesh_of(s));
    EXPECT_NEAR(s->surface_area(), 4.f, 1e-6f);
}

TEST(MeshPly, BinaryBigEndian) {
    TempDir dir("geom");
    expect_quad(
        ply_mesh_of(make_shape(ShapeProps("ply").s("filename", dir.write("be.ply", binary_quad(false))))));
}

TEST(MeshPly, AsciiWithUvVariantsAndComputedNormals) {
    TempDir dir("geom");
    std::string ply =
        "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty double x\r\nproperty double y\r\n"
        "property double z\r\nproperty float texture_u\r\nproperty float texture_v\r\n"
        "element face 1\r\nproperty list uchar uint vertex_index\r\nend_header\r\n"
        "0 0 0 0 0\r\n1 0 0 1 0\r\n0 1 0 0 1\r\n3 0 1 2\r\n";
    auto s = make_shape(ShapeProps("ply").s("filename", dir.write("tri.ply", ply)));
    const TriangleMesh& m = ply_mesh_of(s);
    ASSERT_EQ(m.triangle_count(), 1u);
    EXPECT_EQ(m.uvs[2], Vec2f(0, 1));
    ASSERT_EQ(m.normals.size(), 3u);  // computed, as Mitsuba does without face_normals
    EXPECT_NEAR(m.normals[0].z, 1.f, 1e-6f);
    EXPECT_NEAR(s->surface_area(), 0.5f, 1e-6f);

    auto faceted =
        make_shape(ShapeProps("ply").s("filename", dir.write("tri.ply", ply)).b("face_normals", true));
    EXPECT_TRUE(ply_mesh_of(faceted).normals.empty());
}

TEST(MeshPly, UvNamedUV) {
    TempDir dir("geom");
    std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "property float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\n"
        "end_header\n0 0 0 .1 .2\n1 0 0 +.3 4e-1\n0 1 0 .5 .6\n3 0 1 2\n";
    auto s = make_shape(ShapeProps("ply").s("filename", dir.write("uv.ply", ply)));
    const TriangleMesh& m = ply_mesh_of(s);
    EXPECT_NEAR(m.uvs[1].y, 0.4f, 1e-7f);
}

TEST(MeshPly, MalformedFilesNameTheFile) {
    TempDir dir("geom");
    const std::pair<const char*, std::string> cases[] = {
        {"nomagic.ply", "plx\nformat ascii 1.0\nend_header\n"},
        {"noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"},
        {"badformat.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"},
        {"badtype.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quux x\nend_header\n"},
        {"truncated.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"},
        {"badindex.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 "
         "9\n"},
        {"pentagon.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n5 0 1 2 0 "
         "1\n"},
        {"garbage.ply",
         "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 "
         "2\n"},
        {"noxyz.ply",
         "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nelement face 0\n"
         "property list uchar int vertex_indices\nend_header\n0\n"},
    };
    for (const auto& [name, contents] : cases) {
        SCOPED_TRACE(name);
        std::string file = dir.write(name, contents);
        try {
            make_shape(ShapeProps("ply").s("filename", file));
            ADD_FAILURE() << "no error";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    }
    // Truncated binary body.
    std::string cut = binary_quad(true);
    cut.resize(cut.size() - 20);
    EXPECT_THROW(make_shape(ShapeProps("ply").s("filename", dir.write("cut.ply", cut))), InputError);
}
