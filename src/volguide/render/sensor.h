#pragma once
// Film, reconstruction filters and cameras (Mitsuba 3's hdrfilm, box/gaussian/tent, perspective,
// orthographic).
#include <cstdint>
#include <memory>
#include <string>
#include <utility>

#include "volguide/core/color.h"
#include "volguide/core/object.h"
#include "volguide/core/ray.h"
#include "volguide/core/transform.h"
#include "volguide/render/tonemap.h"

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
    Film(int width, int height, std::shared_ptr<ReconstructionFilter> filter, bool sample_border = false)
        : width_(width), height_(height), filter_(std::move(filter)), sample_border_(sample_border) {}
    int width() const { return width_; }
    int height() const { return height_; }
    const ReconstructionFilter& filter() const { return *filter_; }
    // Mitsuba's hdrfilm `sample_border`: also sample positions up to the filter's border outside
    // the image, so edge pixels receive as many filtered samples as interior ones.
    bool sample_border() const { return sample_border_; }
    // How a PNG of the render is written: the default preview, or an ldrfilm's tonemap.
    const PngTonemap& png_tonemap() const { return png_tonemap_; }
    void set_png_tonemap(const PngTonemap& t) { png_tonemap_ = t; }

private:
    int width_, height_;
    std::shared_ptr<ReconstructionFilter> filter_;
    bool sample_border_ = false;
    PngTonemap png_tonemap_;
};

class Medium;

// Where a sensor sees a world point (light tracing: Mitsuba 3's Sensor::sample_direction for a pinhole):
// the film position in pixels, the direction from the point to the sensor's position p, the distance,
// and the importance per unit solid angle at the sensor divided by dist² (zero when the sensor does not
// see the point: outside the film, behind, or outside the clip range).
struct SensorConnection {
    Point3f p;
    Vec3f d;
    float dist = 0.f;
    Point2f film_pos;
    float weight = 0.f;
};

class Sensor : public Object {
public:
    // The medium the camera sits in (nullptr = vacuum), from the sensor's `medium` reference.
    const Medium* medium() const { return medium_.get(); }
    // film_uv in [0,1]^2 over the film (x right, y down); aperture sample for thin lenses.
    // Returns the world-space ray and its importance weight (1 for pinhole cameras).
    virtual std::pair<Ray, Color3> sample_ray(Point2f film_uv, Point2f aperture) const = 0;
    // Whether sample_ray uses its aperture sample (thin lens): only then does a camera sample draw one,
    // so pinhole renders keep their random-number layout.
    virtual bool needs_aperture_sample() const { return false; }
    // Light tracing (ptracer): whether connect/importance are implemented (pinhole cameras).
    virtual bool supports_connections() const { return false; }
    virtual SensorConnection connect(const Point3f& ref) const { return {}; }
    // For a world direction d leaving the sensor's position: the importance per unit solid angle
    // (the clip range ignored: for emitters at infinity) in `weight`, and the film position.
    virtual SensorConnection importance(const Vec3f& d) const { return {}; }
    const Film& film() const { return *film_; }
    int sample_count() const { return sample_count_; }
    // The sampler's `seed` (default 0); the CLI's --seed overrides it.
    uint64_t seed() const { return seed_; }
    const Transform& to_world() const { return to_world_; }

protected:
    std::shared_ptr<Film> film_;
    int sample_count_ = 4;  // Mitsuba's independent sampler default
    uint64_t seed_ = 0;
    Transform to_world_;
    std::shared_ptr<Medium> medium_;
};

}  // namespace volguide
