#pragma once
// Ray queries over all shapes of a scene (Embree 3 behind a pimpl).
#include <memory>
#include <vector>

#include "volguide/geometry/interaction.h"
#include "volguide/geometry/shape.h"

namespace volguide {

class Accel {
public:
    explicit Accel(const std::vector<const Shape*>& shapes);
    ~Accel();
    Accel(const Accel&) = delete;
    Accel& operator=(const Accel&) = delete;

    // Closest hit with t in (0, ray.tmax); fills si (si.wi in the shading frame).
    bool intersect(const Ray& ray, SurfaceInteraction& si) const;
    // Any hit with t in (0, ray.tmax).
    bool occluded(const Ray& ray) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace volguide
