#include "volguide/integrators/camera_sample.h"

#include "volguide/render/scene.h"

namespace volguide {

Point2f film_position(int x, int y, Vec2f u) { return Point2f(float(x) + u.x, float(y) + u.y); }

FilmSample film_sample(const FilmGrid& grid, uint64_t seed, int x, int y, uint64_t index, uint64_t stream) {
    FilmSample s{Sampler(seed, grid.pixel_index(x, y), index, stream), Point2f(), Point2f()};
    s.pos = film_position(x, y, s.sampler.next_2d());
    s.film_uv = Point2f(s.pos.x / float(grid.width), s.pos.y / float(grid.height));
    return s;
}

Color3 camera_sample_value(const Scene& scene, const Integrator& integrator, Point2f film_uv, Sampler& sampler) {
    const Point2f aperture = scene.sensor().needs_aperture_sample() ? sampler.next_2d() : Point2f(0.5f, 0.5f);
    return camera_sample_value(
        scene.sensor(), film_uv, [&](const CameraRay& camera) { return integrator.Li(scene, sampler, camera); },
        aperture);
}

}  // namespace volguide
