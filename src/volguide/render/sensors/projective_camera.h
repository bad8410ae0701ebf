#pragma once
// Pinhole-style cameras with Mitsuba 3's conventions. Camera space: +z looks forward, +y is up and
// +x is *left* (so image x grows toward camera -x). Film coordinates (u, v) in [0,1]^2 run from the
// top-left corner, x to the right and y down. Rays start on the near plane and end on the far plane.
#include <memory>

#include "volguide/core/properties.h"
#include "volguide/render/sensor.h"

namespace volguide {

class ProjectiveCamera : public Sensor {
public:
    float near_clip() const { return near_clip_; }
    float far_clip() const { return far_clip_; }
    // Film width / height.
    float aspect() const { return aspect_; }

protected:
    // Reads to_world, near_clip, far_clip, focus_distance, shutter_open/close and the <film> and
    // <sampler> children (Mitsuba's defaults when absent).
    explicit ProjectiveCamera(const Properties& props);
    ProjectiveCamera(std::shared_ptr<Film> film, const Transform& to_world, float near_clip, float far_clip);

    float near_clip_ = 1e-2f, far_clip_ = 1e4f, aspect_ = 1.f;

private:
    void check_clip(const Properties* props) const;
};

}  // namespace volguide
