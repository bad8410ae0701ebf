#include "volguide/geometry/instance.h"

#include <stdexcept>

#include "volguide/geometry/surface_frame.h"

namespace volguide {

ShapeGroup::ShapeGroup(const Properties& props) {
    for (const Properties::Entry* e : props.children("shape")) {
        auto shape = std::dynamic_pointer_cast<Shape>(std::get<ObjectPtr>(e->value));
        if (!shape || std::dynamic_pointer_cast<Instance>(shape))
            fail(e->loc, "shapegroup: a group holds plain shapes (no nested shapegroup or instance)");
        if (shape->is_emitter()) fail(e->loc, "shapegroup: shapes of a group cannot be emitters (as in Mitsuba)");
        if (shape->interior_medium() || shape->exterior_medium())
            fail(e->loc, "shapegroup: shapes of a group cannot bound media");
        shapes_.push_back(shape);
        bbox_.expand(shape->bbox());
    }
    if (shapes_.empty()) props.fail_here("shapegroup: the group has no shapes");
}

Instance::Instance(const Properties& props) {
    auto groups = props.children("shape");
    if (groups.size() != 1) props.fail_here("instance: exactly one referenced shapegroup is required");
    group_ = std::dynamic_pointer_cast<ShapeGroup>(std::get<ObjectPtr>(groups[0]->value));
    if (!group_) fail(groups[0]->loc, "instance: the referenced shape is not a shapegroup");
    to_world_ = props.get_transform("to_world");
    const BBox3f b = group_->bbox();
    for (int i = 0; i < 8; ++i)
        bbox_.expand(to_world_.apply_point(
            Point3f(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z)));
}

SurfaceInteraction Instance::compute_surface_interaction(const Ray&, float, uint32_t, Vec2f) const {
    throw std::logic_error("Instance::compute_surface_interaction: hits on instances are resolved by the Accel");
}

PositionSample Instance::sample_position(Point2f) const {
    throw std::logic_error("Instance::sample_position: instances are never emitters");
}

SurfaceInteraction Instance::interaction(const Shape& inner, const Ray& ray, float t, uint32_t prim_index,
                                         Vec2f prim_uv) const {
    const Transform to_object = to_world_.inverse();
    // The same parametric t in both spaces: the direction is transformed, not renormalised.
    const Ray local(to_object.apply_point(ray.o), to_object.apply_vector(ray.d), ray.tmax);
    SurfaceInteraction si = inner.compute_surface_interaction(local, t, prim_index, prim_uv);
    si.t = t;
    si.p = to_world_.apply_point(si.p);
    si.n = normalize(to_world_.apply_normal(si.n));
    si.sh_frame.n = normalize(to_world_.apply_normal(si.sh_frame.n));
    si.dp_du = to_world_.apply_vector(si.dp_du);
    si.dp_dv = to_world_.apply_vector(si.dp_dv);
    finalize_shading_frame(si, ray);
    return si;
}

ObjectPtr create_shapegroup_shape(const Properties& props) {
    return std::make_shared<ShapeGroup>(props);
}

ObjectPtr create_instance_shape(const Properties& props) {
    return std::make_shared<Instance>(props);
}

}  // namespace volguide
