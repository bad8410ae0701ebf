#pragma once
// Mesh file readers (object space, no transform applied). Errors are InputErrors at `loc`
// whose message names the file.
#include <string>

#include "volguide/core/error.h"
#include "volguide/core/properties.h"
#include "volguide/geometry/shape.h"

namespace volguide {

// Wavefront OBJ: triangles and polygons (fan-triangulated as Mitsuba), vertices shared per
// distinct (position, uv, normal) triple. flip_tex_coords maps v to 1 - v.
TriangleMesh read_obj(const std::string& path, bool flip_tex_coords, const SourceLocation& loc);

// Stanford PLY (ascii, binary_little_endian, binary_big_endian): vertex x y z [nx ny nz]
// [u v | s t | texture_u texture_v | texture_s texture_t], face vertex_indices|vertex_index lists
// of 3 or 4 entries (quads split into two triangles). Other elements and properties are skipped.
TriangleMesh read_ply(const std::string& path, const SourceLocation& loc);

// Mitsuba's `.serialized` format (zlib-compressed, versions 3 and 4), shape `shape_index` of the file.
// face_normals: the file asks for flat shading. Every size is checked against the file and
// core/memory.h's budget before allocating.
struct SerializedMesh {
    TriangleMesh mesh;
    bool face_normals = false;
};
SerializedMesh read_serialized(const std::string& path, int64_t shape_index, const SourceLocation& loc);

// Resolves the `filename` parameter: as given, or relative to the directory of the scene file
// that declared it. Fails with "file not found" otherwise.
std::string resolve_filename(const Properties& props, const std::string& name = "filename");

}  // namespace volguide
