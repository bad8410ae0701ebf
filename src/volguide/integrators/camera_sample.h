#pragma once
// One camera sample, from its pixel and index to the value the film splats: the one place that
// draws it, shared by the render loop, the pixel estimate and tools/replay_sample, so that a
// sample replayed is the sample rendered.
//  - film_sample: the sample's random stream Sampler(seed, pixel index, sample, stream) over the
//    sampled grid (the film plus the filter's border with sample_border) and its film position,
//    jittered uniformly in the pixel by the stream's first two dimensions;
//  - camera_sample_value: the sensor's ray through the film position, the radiance along it (the
//    integrator's Li, or any function of the camera ray) times the sensor's weight.
#include <cstdint>

#include "volguide/core/sampler.h"
#include "volguide/integrators/integrator.h"
#include "volguide/render/sensor.h"

namespace volguide {

// The grid of pixels a render samples: the film, and `border` pixels around it (sample_border).
struct FilmGrid {
    int width = 0, height = 0;  // the film's
    int border = 0;
    // Row-major over the grid, the border included: the sampler's pixel index.
    uint64_t pixel_index(int x, int y) const {
        return uint64_t(y + border) * uint64_t(width + 2 * border) + uint64_t(x + border);
    }
};

struct FilmSample {
    Sampler sampler;  // the sample's stream, its first two dimensions consumed by the jitter
    Point2f pos;      // film position in pixels (where the film splats the value)
    Point2f film_uv;  // pos over the film's size
};

// Sample `index` of pixel (x, y) (film pixels; negative or beyond the film in the border).
FilmSample film_sample(const FilmGrid& grid, uint64_t seed, int x, int y, uint64_t index, uint64_t stream = 0);
// The same with the jitter `u` given (in [0, 1)^2; e.g. stratified over the pixel).
Point2f film_position(int x, int y, Vec2f u);

// The value of a camera sample at film_uv: `radiance(camera_ray)` along the sensor's ray, times
// the sensor's weight.
// Without a sampler the aperture sample is the lens centre: a thin lens is seen as a pinhole (the
// guiding pre-passes use this for estimates that only shape probabilities).
template <typename Radiance>
Color3 camera_sample_value(const Sensor& sensor, Point2f film_uv, Radiance&& radiance,
                           Point2f aperture = Point2f(0.5f, 0.5f)) {
    const auto [ray, weight] = sensor.sample_ray(film_uv, aperture);
    return weight * radiance(CameraRay{ray, film_uv});
}
// With the integrator's Li; the sensor's aperture sample (if it needs one) is the sampler's next 2D.
Color3 camera_sample_value(const Scene& scene, const Integrator& integrator, Point2f film_uv, Sampler& sampler);

}  // namespace volguide
