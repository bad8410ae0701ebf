#pragma once
// Film, reconstruction filters and cameras (Mitsuba 3's hdrfilm, box/gaussian/tent, perspective,
// orthographic).
#include <memory>
#include <string>
#include <utility>

#include "volguide/core/color.h"
#include "volguide/core/object.h"
#include "volguide/core/ray.h"
#include "volguide/core/transform.h"

namespace volguide {

// Separable, radially symmetric 1-D filter: weight(x, y) = eval(x) * eval(y).
class ReconstructionFilter : public Object {
public:
    virtual float eval(float x) const = 0;
    float radius() const { return radius_; }

protected:
    float radius_ = 0.5f;
};

class Film : public Object {
public:
    Film(int width, int height, std::shared_ptr<ReconstructionFilter> filter)
        : width_(width), height_(height), filter_(std::move(filter)) {}
    int width() const { return width_; }
    int height() const { return height_; }
    const ReconstructionFilter& filter() const { return *filter_; }

private:
    int width_, height_;
    std::shared_ptr<ReconstructionFilter> filter_;
};

class Sensor : public Object {
public:
    // film_uv in [0,1]^2 over the film (x right, y down); aperture sample for thin lenses.
    // Returns the world-space ray and its importance weight (1 for pinhole cameras).
    virtual std::pair<Ray, Color3> sample_ray(Point2f film_uv, Point2f aperture) const = 0;
    const Film& film() const { return *film_; }
    int sample_count() const { return sample_count_; }
    const Transform& to_world() const { return to_world_; }

protected:
    std::shared_ptr<Film> film_;
    int sample_count_ = 4;  // Mitsuba's independent sampler default
    Transform to_world_;
};

}  // namespace volguide
