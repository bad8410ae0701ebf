#pragma once
// Mitsuba 3's `sdfgrid`: a signed distance function sampled at the corners of a grid of voxels over
// the object-space unit cube, trilinear in between. Each voxel the zero level set crosses is one Embree
// user primitive, bounded by Hansson-Söderlund and Akenine-Möller's tight box (the edge crossings);
// a ray meets it where the cubic the trilinear interpolant becomes along the ray has its first root in
// the voxel (Hansson-Söderlund, Evans and Akenine-Möller, JCGT 2022: the cubic's derivative roots
// bracket the first sign change, then false position, as Mitsuba's scalar variant). The geometric
// normal is the SDF's gradient by central differences across the hit's voxel; `normals="smooth"`
// (default) blends the gradients of the eight voxels nearest the hit (the JCGT paper's smooth normals),
// "analytic" uses the geometric one. No uv (0), no area (0): it cannot be an area emitter (Mitsuba's
// limits). docs/theory.md §21.
#include <cstdint>
#include <vector>

#include "volguide/core/transform.h"
#include "volguide/geometry/shape.h"

namespace volguide {

// Corner values, x fastest: values[(z * ny + y) * nx + x], each dimension >= 2.
struct SdfValues {
    int nx = 0, ny = 0, nz = 0;
    std::vector<float> values;
};

class SdfGrid final : public Shape {
  public:
    // Throws std::invalid_argument for a grid smaller than 2 per axis, a value count that does not
    // match, or no voxel crossed by the surface.
    SdfGrid(SdfValues grid, const Transform& to_world, bool smooth_normals);
    // The plugin: `filename` (a one-channel .vol), `normals`, `to_world`, a bsdf child.
    explicit SdfGrid(const Properties& props);

    BBox3f bbox() const override;
    float surface_area() const override { return 0.f; }
    uint32_t primitive_count() const override { return uint32_t(voxels_.size()); }
    BBox3f primitive_bbox(uint32_t prim) const override { return boxes_[prim]; }
    bool intersect_primitive(const Ray& ray, uint32_t prim, float& t, Vec2f& prim_uv) const override;
    SurfaceInteraction compute_surface_interaction(const Ray& ray, float t, uint32_t prim_index,
                                                   Vec2f prim_uv) const override;
    PositionSample sample_position(Point2f u) const override { return {}; }
    float pdf_position(const PositionSample&) const override { return 0.f; }
    std::string to_string() const override;

    // The trilinear SDF at an object-space point (clamped to the grid), and its gradient across the
    // voxel `v` (central differences between the voxel's faces through p).
    float value(const Point3f& p) const;
    Vec3f voxel_gradient(const Point3f& p, int vx, int vy, int vz) const;
    Vec3f smooth_normal(const Point3f& p) const;  // object space, not normalised

  private:
    void build(const Transform& to_world, bool smooth_normals);
    float corner(int x, int y, int z) const;
    bool tight_box(int x, int y, int z, BBox3f& box) const;  // voxel-local [0,1]^3; false if not crossed

    SdfValues grid_;
    Transform to_world_, to_object_;
    bool smooth_ = true;
    Vec3f voxel_size_;              // 1 / (n - 1) per axis
    std::vector<uint32_t> voxels_;  // crossed voxels: x + (nx - 1) (y + (ny - 1) z)
    std::vector<BBox3f> boxes_;     // their tight boxes, world space
};

}  // namespace volguide
