// Mitsuba `.serialized` meshes (issue 40): versions 3 and 4, float32 and float64, shape_index over a
// multi-shape file, face normals, and malformed files (errors name the file and what is wrong; sizes
// are checked before anything is allocated).
#include <gtest/gtest.h>

#include <filesystem>

#include "support/cli.h"
#include "support/serialized_writer.h"
#include "test_shape_util.h"
#include "volguide/core/error.h"
#include "volguide/geometry/shapes/mesh_files.h"

using namespace volguide;
using namespace volguide::test;

namespace {

std::string error_of(const std::string& path, int64_t index = 0) {
    try {
        (void)read_serialized(path, index, test_loc());
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(MeshSerialized, Version4SinglePrecision) {
    TempDir dir("serialized");
    const std::string path = dir.write("quad.serialized", serialized_file({serialized_quad()}, 4));
    SerializedMesh m = read_serialized(path, 0, test_loc());
    ASSERT_EQ(m.mesh.positions.size(), 4u);
    EXPECT_EQ(m.mesh.indices, (std::vector<uint32_t>{0, 1, 2, 2, 3, 0}));
    EXPECT_EQ(m.mesh.positions[2], Point3f(1, 1, 0));
    ASSERT_EQ(m.mesh.normals.size(), 4u);
    EXPECT_EQ(m.mesh.normals[1], Normal3f(0, 0, 1));
    ASSERT_EQ(m.mesh.uvs.size(), 4u);
    EXPECT_EQ(m.mesh.uvs[3], Vec2f(0, 1));
    EXPECT_FALSE(m.face_normals);
}

TEST(MeshSerialized, Version3DoublePrecisionShapeIndex) {
    TempDir dir("serialized");
    SerializedShape a = serialized_quad(0.f), b = serialized_quad(2.5f), c = serialized_quad(-1.f);
    b.double_precision = true;
    b.normals.clear();
    b.face_normals = true;
    const std::string path = dir.write("three.serialized", serialized_file({a, b, c}, 3));
    SerializedMesh m = read_serialized(path, 1, test_loc());
    ASSERT_EQ(m.mesh.positions.size(), 4u);
    EXPECT_EQ(m.mesh.positions[0], Point3f(-1, -1, 2.5f));
    EXPECT_TRUE(m.mesh.normals.empty());
    EXPECT_TRUE(m.face_normals);
    EXPECT_EQ(read_serialized(path, 2, test_loc()).mesh.positions[0], Point3f(-1, -1, -1));
    EXPECT_NE(error_of(path, 3).find("out of range: the file holds 3 shape(s)"), std::string::npos) << error_of(path, 3);
}

TEST(MeshSerialized, ThroughTheShapeFactory) {
    TempDir dir("serialized");
    const std::string path = dir.write("quad.serialized", serialized_file({serialized_quad(), serialized_quad(1.f)}));
    ShapeProps sp("serialized");
    sp.s("filename", path);
    sp.set("shape_index", "integer", int64_t(1));
    auto shape = make_shape(sp);
    ASSERT_TRUE(shape);
    EXPECT_FLOAT_EQ(shape->surface_area(), 4.f);
    EXPECT_FLOAT_EQ(shape->bbox().lo.z, 1.f);
}

TEST(MeshSerialized, MalformedFilesNameFileAndProblem) {
    TempDir dir("serialized");
    const std::string good = serialized_file({serialized_quad()});
    const auto expect = [&](const std::string& name, const std::string& contents, const std::string& what) {
        const std::string path = dir.write(name, contents);
        const std::string err = error_of(path);
        EXPECT_NE(err.find(path), std::string::npos) << err;
        EXPECT_NE(err.find(what), std::string::npos) << err;
    };
    expect("empty.serialized", "", "truncated shape header");
    expect("magic.serialized", "PLY!" + good.substr(4), "no serialized shape header");
    std::string v5 = good;
    v5[2] = 5;
    expect("v5.serialized", v5, "unsupported format version 5");
    expect("cut.serialized", good.substr(0, 30), "ends inside");
    std::string corrupt = good;
    corrupt[5] = char(corrupt[5] ^ 0x01);  // the zlib header's check bits
    expect("corrupt.serialized", corrupt, "corrupt compressed data");
    SerializedShape huge = serialized_quad();
    huge.vertex_count = int64_t(1) << 31;  // 2^31 vertices declared, 4 stored: refused before allocating
    expect("huge.serialized", serialized_file({huge}), "more than the rest of the file can hold");
    SerializedShape bad_index = serialized_quad();
    bad_index.indices[4] = 7;
    expect("index.serialized", serialized_file({bad_index}), "triangle index 7 is out of range (4 vertices)");
    SerializedShape nan = serialized_quad();
    nan.positions[1] = std::numeric_limits<float>::quiet_NaN();
    expect("nan.serialized", serialized_file({nan}), "non-finite value among the positions");
    EXPECT_NE(error_of(dir.write("neg.serialized", good), -1).find("shape_index must be >= 0"), std::string::npos);
}

}  // namespace
