// Shape plugins by XML type (Mitsuba 3 names).
#include <string_view>

#include "volguide/geometry/instance.h"
#include "volguide/geometry/shapes/shape_plugins.h"
#include "volguide/scene/factories.h"

namespace volguide {

ObjectPtr create_shape(const Properties& props) {
    const std::string& type = props.type();
    if (type == "obj") return create_obj_shape(props);
    if (type == "ply") return create_ply_shape(props);
    if (type == "serialized") return create_serialized_shape(props);
    if (type == "rectangle") return create_rectangle_shape(props);
    if (type == "cube") return create_cube_shape(props);
    if (type == "sphere") return create_sphere_shape(props);
    if (type == "disk") return create_disk_shape(props);
    if (type == "cylinder") return create_cylinder_shape(props);
    if (type == "sdfgrid") return create_sdfgrid_shape(props);
    if (type == "shapegroup") return create_shapegroup_shape(props);
    if (type == "instance") return create_instance_shape(props);
    props.fail_here("unsupported {} plugin '{}' (supported: obj, ply, serialized, rectangle, cube, sphere, disk, cylinder, "
                    "sdfgrid, shapegroup, instance)",
                    props.category(), type);
}

}  // namespace volguide
