#pragma once
// The explicit factory table: one function per XML category, each in the module that owns
// the plugins. scene/loader.cpp dispatches on the tag. Unknown types are input errors.
#include "volguide/core/object.h"
#include "volguide/core/properties.h"

namespace volguide {

ObjectPtr create_bsdf(const Properties& props);        // render/bsdfs/bsdf_factory.cpp
ObjectPtr create_texture(const Properties& props);     // render/textures/texture_factory.cpp
ObjectPtr create_emitter(const Properties& props);     // render/emitters/emitter_factory.cpp
ObjectPtr create_shape(const Properties& props);       // geometry/shape_factory.cpp
ObjectPtr create_sensor(const Properties& props);      // render/sensor_factory.cpp
ObjectPtr create_film(const Properties& props);        // render/sensor_factory.cpp
ObjectPtr create_rfilter(const Properties& props);     // render/sensor_factory.cpp
ObjectPtr create_sampler(const Properties& props);     // render/sensor_factory.cpp
ObjectPtr create_integrator(const Properties& props);  // integrators/integrator_factory.cpp
ObjectPtr create_medium(const Properties& props);      // media/media_factory.cpp
ObjectPtr create_phase(const Properties& props);       // media/media_factory.cpp
ObjectPtr create_volume(const Properties& props);      // media/media_factory.cpp

}  // namespace volguide
