#pragma once
// Triangle-mesh shape shared by obj, ply, rectangle and cube: world-space vertices, optional
// per-vertex normals and uvs, area-weighted position sampling. Follows Mitsuba 3's Mesh
// (geometric normal from the winding, shading normal interpolated from vertex normals,
// uv = barycentrics (b1, b2) when the mesh has no texture coordinates).
#include <string>

#include "volguide/core/distribution.h"
#include "volguide/core/transform.h"
#include "volguide/geometry/shape.h"

namespace volguide {

// Mesh parameters common to every mesh plugin.
struct MeshOptions {
    Transform to_world;
    bool face_normals = false;  // drop vertex normals: faceted look
    bool flip_normals = false;
};

// Applies to_world to positions and normals (inverse transpose, renormalized).
void transform_mesh(TriangleMesh& mesh, const Transform& to_world);
// Smooth vertex normals weighted by the corner angles (Thürmer & Wüthrich 1998, as Mitsuba).
void compute_vertex_normals(TriangleMesh& mesh);

class MeshShape : public Shape {
  public:
    // `mesh` is in object space; `name` (e.g. the file name) is used in error messages.
    // Vertex normals are dropped when face_normals is set, and computed when the mesh has none
    // and compute_missing_normals is true (OBJ/PLY do, as Mitsuba).
    MeshShape(const Properties& props, TriangleMesh mesh, const MeshOptions& opts, std::string name,
              bool compute_missing_normals);

    BBox3f bbox() const override { return bbox_; }
    float surface_area() const override { return area_; }
    const TriangleMesh* triangle_mesh() const override { return &mesh_; }
    SurfaceInteraction compute_surface_interaction(const Ray& ray, float t, uint32_t prim_index,
                                                   Vec2f prim_uv) const override;
    PositionSample sample_position(Point2f u) const override;
    int attribute_channels(const std::string& name) const override;
    Color3 eval_attribute(const std::string& name, const SurfaceInteraction& si) const override;
    float pdf_position(const PositionSample&) const override { return inv_area_; }
    bool flip_normals() const { return flip_normals_; }
    const std::string& name() const { return name_; }
    std::string to_string() const override;

  private:
    void check_attributes(const Properties& props) const;
    const MeshAttribute* find_attribute(const std::string& name) const;

    TriangleMesh mesh_;
    DiscreteDistribution area_distr_;
    BBox3f bbox_;
    float area_ = 0.f, inv_area_ = 0.f;
    bool flip_normals_ = false;
    std::string name_;
};

// Reads the parameters mesh plugins share (to_world, flip_normals and, for Mitsuba Mesh
// subclasses, face_normals).
MeshOptions read_mesh_options(const Properties& props, bool accepts_face_normals = true);

}  // namespace volguide
