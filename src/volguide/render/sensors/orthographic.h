#pragma once
// Mitsuba 3's `orthographic` camera: parallel rays along camera +z. The film covers camera-space
// x in [-1, 1] and y in [-1/aspect, 1/aspect]; scale it with to_world to choose the extent.
#include "volguide/render/sensors/projective_camera.h"

namespace volguide {

class OrthographicCamera final : public ProjectiveCamera {
public:
    explicit OrthographicCamera(const Properties& props);
    OrthographicCamera(std::shared_ptr<Film> film, const Transform& to_world, float near_clip = 1e-2f,
                       float far_clip = 1e4f);
    std::pair<Ray, Color3> sample_ray(Point2f film_uv, Point2f aperture) const override;
    std::string to_string() const override;

private:
    void configure();
    Vec3f direction_;
};

}  // namespace volguide
