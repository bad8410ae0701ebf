#include "volguide/render/sensors/orthographic.h"

#include <fmt/format.h>

namespace volguide {

OrthographicCamera::OrthographicCamera(const Properties& props) : ProjectiveCamera(props) {
    configure();
    if (!all_finite(direction_)) props.fail_at("to_world", "orthographic: degenerate to_world transform");
}

OrthographicCamera::OrthographicCamera(std::shared_ptr<Film> film, const Transform& to_world, float near_clip,
                                       float far_clip)
    : ProjectiveCamera(std::move(film), to_world, near_clip, far_clip) {
    configure();
}

void OrthographicCamera::configure() { direction_ = normalize(to_world_.apply_vector(Vec3f(0.f, 0.f, 1.f))); }

std::pair<Ray, Color3> OrthographicCamera::sample_ray(Point2f uv, Point2f) const {
    Point3f near_p((1.f - 2.f * uv.x), (1.f - 2.f * uv.y) / aspect_, near_clip_);
    return {Ray(to_world_.apply_point(near_p), direction_, far_clip_ - near_clip_), Color3(1.f)};
}

std::string OrthographicCamera::to_string() const {
    return fmt::format("orthographic[near_clip={}, far_clip={}]", near_clip_, far_clip_);
}

}  // namespace volguide
