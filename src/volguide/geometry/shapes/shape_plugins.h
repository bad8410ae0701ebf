#pragma once
// One constructor function per shape plugin (XML type), used by geometry/shape_factory.cpp.
#include "volguide/core/object.h"
#include "volguide/core/properties.h"

namespace volguide {

ObjectPtr create_obj_shape(const Properties& props);
ObjectPtr create_ply_shape(const Properties& props);
ObjectPtr create_serialized_shape(const Properties& props);
ObjectPtr create_rectangle_shape(const Properties& props);
ObjectPtr create_cube_shape(const Properties& props);
ObjectPtr create_sphere_shape(const Properties& props);
ObjectPtr create_disk_shape(const Properties& props);
ObjectPtr create_cylinder_shape(const Properties& props);
ObjectPtr create_sdfgrid_shape(const Properties& props);

}  // namespace volguide
