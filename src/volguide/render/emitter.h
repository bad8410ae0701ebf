#pragma once
// Emitters, in Mitsuba 3's convention. sample_direction returns the sample and the weight
// radiance / pdf (solid angle at the reference; for delta emitters intensity / dist^2), without
// visibility. eval() returns the radiance leaving the emitter towards si.wi: for surface emitters
// si is the hit (si.wi local); for emitters at infinity si.wi is the world direction -ray.d.
#include <cstdint>
#include <utility>

#include "volguide/core/bbox.h"
#include "volguide/core/color.h"
#include "volguide/core/object.h"
#include "volguide/core/ray.h"
#include "volguide/geometry/interaction.h"
#include "volguide/geometry/shape.h"

namespace volguide {

class Medium;

namespace emitter_flags {
enum : uint32_t {
    None = 0,
    DeltaPosition = 1u << 0,
    DeltaDirection = 1u << 1,
    Infinite = 1u << 2,
    Surface = 1u << 3,
};
}

// A ray leaving an emitter (for photon tracing). weight is the flux the ray carries for one sample,
// Mitsuba's sample_ray convention: emitted radiance x cos / (pdf_pos x pdf_dir), so that the
// expected weight is the emitter's power(). Zero weight = no emission for this sample.
struct RaySample {
    Ray ray;                // ray.d is the (unit) direction of propagation
    Color3 weight{0.f};
    Normal3f n{0.f};        // surface normal at the origin (area emitters, emitting side); else zero
};

class Emitter : public Object {
public:
    // Emission sampling: u_pos picks the origin, u_dir the direction.
    virtual RaySample sample_ray(Point2f u_pos, Point2f u_dir) const = 0;
    // Total flux (W) emitted into the scene, defined as E[sample_ray().weight]. Emitters at
    // infinity (and directional) count the flux through the disk of the scene's bounding sphere,
    // so call it after set_scene_bounds.
    virtual Color3 power() const = 0;

    virtual std::pair<DirectionSample, Color3> sample_direction(const Interaction& ref, Point2f u) const = 0;
    virtual float pdf_direction(const Interaction& ref, const DirectionSample& ds) const = 0;
    virtual Color3 eval(const SurfaceInteraction& si) const = 0;

    // Called once the scene is assembled (emitters at infinity need its bounding sphere).
    virtual void set_scene_bounds(const BBox3f& bounds) {}
    // Area emitters are told which shape they sit on.
    virtual void set_shape(const Shape* shape) { shape_ = shape; }
    const Shape* shape() const { return shape_; }
    // The medium the emitter sits in (nullptr = vacuum); for area emitters the shape's media apply.
    const Medium* medium() const { return medium_.get(); }

    uint32_t flags() const { return flags_; }
    bool is_delta() const { return (flags_ & (emitter_flags::DeltaPosition | emitter_flags::DeltaDirection)) != 0; }
    bool is_infinite() const { return (flags_ & emitter_flags::Infinite) != 0; }

protected:
    uint32_t flags_ = 0;
    const Shape* shape_ = nullptr;
    std::shared_ptr<Medium> medium_;
};

}  // namespace volguide
