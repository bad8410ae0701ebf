#pragma once
// Mitsuba 3's `shapegroup` and `instance`: a group of shapes built once into its own Embree scene
// and placed any number of times by Embree instances, each with its own to_world. Groups hold
// neither emitters nor media (Mitsuba does not instance emitters; an instanced medium boundary
// would need per-instance media), and do not nest.
#include <memory>
#include <vector>

#include "volguide/core/object.h"
#include "volguide/core/properties.h"
#include "volguide/core/transform.h"
#include "volguide/geometry/shape.h"

namespace volguide {

class ShapeGroup final : public Object {
  public:
    explicit ShapeGroup(const Properties& props);
    // In the order of the file: index = Embree geometry id inside the group's scene.
    const std::vector<std::shared_ptr<Shape>>& shapes() const { return shapes_; }
    BBox3f bbox() const { return bbox_; }
    std::string to_string() const override { return "ShapeGroup[]"; }

  private:
    std::vector<std::shared_ptr<Shape>> shapes_;
    BBox3f bbox_;
};

class Instance final : public Shape {
  public:
    explicit Instance(const Properties& props);
    const ShapeGroup& group() const { return *group_; }
    const Transform& to_world() const { return to_world_; }

    BBox3f bbox() const override { return bbox_; }
    float surface_area() const override { return 0.f; }  // never an emitter
    // The Accel resolves hits on instances with interaction(); these are never called.
    SurfaceInteraction compute_surface_interaction(const Ray&, float, uint32_t, Vec2f) const override;
    PositionSample sample_position(Point2f) const override;

    // The hit of `ray` (world space) at t on primitive prim_index of the group's shape `inner`,
    // in world space; si.shape is `inner` (its BSDF).
    SurfaceInteraction interaction(const Shape& inner, const Ray& ray, float t, uint32_t prim_index,
                                   Vec2f prim_uv) const;
    std::string to_string() const override { return "Instance[]"; }

  private:
    std::shared_ptr<ShapeGroup> group_;
    Transform to_world_;
    BBox3f bbox_;
};

ObjectPtr create_shapegroup_shape(const Properties& props);
ObjectPtr create_instance_shape(const Properties& props);

}  // namespace volguide
