#pragma once
// Constructors of the emitter plugins (one file each), dispatched on by create_emitter().
#include "volguide/core/object.h"
#include "volguide/core/properties.h"

namespace volguide {

ObjectPtr make_area_emitter(const Properties& props);         // area.cpp
ObjectPtr make_point_emitter(const Properties& props);        // point.cpp
ObjectPtr make_spot_emitter(const Properties& props);         // spot.cpp
ObjectPtr make_directional_emitter(const Properties& props);  // directional.cpp
ObjectPtr make_constant_emitter(const Properties& props);     // constant.cpp
ObjectPtr make_envmap_emitter(const Properties& props);       // envmap.cpp
ObjectPtr make_projector_emitter(const Properties& props);    // projector.cpp

}  // namespace volguide
