// The mesh-backed shape plugins: obj, ply (from files), rectangle and cube (built in).
#include <filesystem>

#include "volguide/geometry/shapes/mesh_files.h"
#include "volguide/geometry/shapes/mesh_shape.h"
#include "volguide/geometry/shapes/shape_plugins.h"

namespace volguide {

namespace {
std::string file_name_of(const std::string& path) {
    return std::filesystem::path(path).filename().string();
}

// A linear map with negative determinant mirrors the winding; analytic Mitsuba shapes
// (rectangle) transform their normal with the inverse transpose instead, which does not flip.
bool flips_orientation(const Transform& t) {
    const auto& m = t.matrix().m;
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    return det < 0.0;
}
}  // namespace

ObjectPtr create_obj_shape(const Properties& props) {
    std::string path = resolve_filename(props);
    bool flip_tex_coords = props.get_bool("flip_tex_coords", true);
    MeshOptions opts = read_mesh_options(props);
    TriangleMesh mesh = read_obj(path, flip_tex_coords, props.location_of("filename"));
    return std::make_shared<MeshShape>(props, std::move(mesh), opts, file_name_of(path), true);
}

ObjectPtr create_ply_shape(const Properties& props) {
    std::string path = resolve_filename(props);
    MeshOptions opts = read_mesh_options(props);
    TriangleMesh mesh = read_ply(path, props.location_of("filename"));
    return std::make_shared<MeshShape>(props, std::move(mesh), opts, file_name_of(path), true);
}

// Mitsuba's `.serialized` meshes: shape `shape_index` (default 0) of the file; a file's request for
// face normals is honoured as `face_normals` (Mitsuba's loader does the same).
ObjectPtr create_serialized_shape(const Properties& props) {
    std::string path = resolve_filename(props);
    MeshOptions opts = read_mesh_options(props);
    SerializedMesh s = read_serialized(path, props.get_int("shape_index", 0), props.location_of("filename"));
    if (s.face_normals) opts.face_normals = true;
    return std::make_shared<MeshShape>(props, std::move(s.mesh), opts, file_name_of(path), true);
}

// Mitsuba 3's rectangle: [-1,1]^2 in the z=0 plane, normal +z, uv = (x+1)/2, (y+1)/2.
ObjectPtr create_rectangle_shape(const Properties& props) {
    MeshOptions opts = read_mesh_options(props, /*accepts_face_normals=*/false);
    TriangleMesh mesh;
    mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    mesh.indices = {0, 1, 2, 2, 3, 0};
    if (flips_orientation(opts.to_world)) mesh.indices = {0, 2, 1, 2, 0, 3};
    return std::make_shared<MeshShape>(props, std::move(mesh), opts, "rectangle", false);
}

// Mitsuba 3's cube: [-1,1]^3 as 24 vertices (4 per face) with per-face normals and each face
// mapped onto [0,1]^2 in uv.
ObjectPtr create_cube_shape(const Properties& props) {
    MeshOptions opts = read_mesh_options(props);
    TriangleMesh mesh;
    // Faces in order -y, +y, +x, +z, -x, -z; corners listed so that (0,1,2), (3,0,2) face outwards.
    mesh.positions = {{1, -1, -1}, {1, -1, 1},   {-1, -1, 1}, {-1, -1, -1}, {1, 1, -1},   {-1, 1, -1},
                      {-1, 1, 1},  {1, 1, 1},    {1, -1, -1}, {1, 1, -1},   {1, 1, 1},    {1, -1, 1},
                      {1, -1, 1},  {1, 1, 1},    {-1, 1, 1},  {-1, -1, 1},  {-1, -1, 1},  {-1, 1, 1},
                      {-1, 1, -1}, {-1, -1, -1}, {1, 1, -1},  {1, -1, -1},  {-1, -1, -1}, {-1, 1, -1}};
    const Normal3f face_n[6] = {{0, -1, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {-1, 0, 0}, {0, 0, -1}};
    for (int f = 0; f < 6; ++f) {
        for (int k = 0; k < 4; ++k) mesh.normals.push_back(face_n[f]);
        mesh.uvs.insert(mesh.uvs.end(), {{0, 1}, {1, 1}, {1, 0}, {0, 0}});
        uint32_t b = uint32_t(4 * f);
        mesh.indices.insert(mesh.indices.end(), {b, b + 1, b + 2, b + 3, b, b + 2});
    }
    return std::make_shared<MeshShape>(props, std::move(mesh), opts, "cube", false);
}

}  // namespace volguide
