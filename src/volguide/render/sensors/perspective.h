#pragma once
// Mitsuba 3's `perspective` pinhole camera and its `thinlens` camera (the same film mapping, rays from a
// disk-shaped aperture focused on the plane at focus_distance).
#include <string>

#include "volguide/render/sensors/projective_camera.h"

namespace volguide {

// Mitsuba's field-of-view rules: converts `fov` degrees measured along `axis` (x, y, diagonal,
// smaller, larger) of a film with the given aspect (width / height) to the horizontal fov.
// Throws std::invalid_argument for an unknown axis.
double horizontal_fov(double fov_deg, const std::string& axis, double aspect);
// Mitsuba's `focal_length` ("50mm": 35 mm film equivalent) as a diagonal fov in degrees; nullopt-like
// negative value when the string cannot be parsed.
double focal_length_to_diagonal_fov(const std::string& focal_length);

class PerspectiveCamera final : public ProjectiveCamera {
  public:
    explicit PerspectiveCamera(const Properties& props);
    // Programmatic construction (tests): horizontal fov in degrees.
    PerspectiveCamera(std::shared_ptr<Film> film, const Transform& to_world, float x_fov_deg,
                      float near_clip = 1e-2f, float far_clip = 1e4f);

    std::pair<Ray, Color3> sample_ray(Point2f film_uv, Point2f aperture) const override;
    float x_fov() const { return x_fov_; }
    bool needs_aperture_sample() const override { return aperture_radius_ > 0.f; }
    // Light tracing: the pinhole only (a thin lens has no connection here).
    bool supports_connections() const override { return aperture_radius_ == 0.f; }
    SensorConnection connect(const Point3f& ref) const override;
    SensorConnection importance(const Vec3f& d) const override;
    std::string to_string() const override;

  private:
    void configure(const Properties* props);
    void read_lens(const Properties& props);
    // The film position and importance of a camera-space direction `local` (z forward, unnormalised).
    SensorConnection project(const Vec3f& local) const;
    float x_fov_;
    float tan_half_x_;                        // tan(x_fov / 2)
    Vec2f principal_point_offset_{0.f, 0.f};  // in film units (fractions of width and height)
    Point3f origin_;
    float aperture_radius_ = 0.f;  // thinlens only; 0 = pinhole
    float focus_distance_ = 0.f;
};

}  // namespace volguide
