#include "volguide/render/sensors/perspective.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "volguide/core/warp.h"

namespace volguide {

namespace {
constexpr double kPi = 3.14159265358979323846;
double to_rad(double d) {
    return d * kPi / 180.0;
}
double to_deg(double r) {
    return r * 180.0 / kPi;
}

// Mitsuba forbids scale (and shear) in a pinhole's to_world: the linear part M must satisfy
// M M^T = I within 1e-3. A mirror (scale -1) passes.
bool has_scale(const Transform& t) {
    const auto& m = t.matrix().m;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) {
            double sum = m[i][0] * m[j][0] + m[i][1] * m[j][1] + m[i][2] * m[j][2];
            if (std::abs(sum - (i == j ? 1.0 : 0.0)) > 1e-3) return true;
        }
    return false;
}
}  // namespace

double horizontal_fov(double fov, const std::string& axis_in, double aspect) {
    std::string axis = axis_in;
    for (auto& ch : axis) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    char which = 0;  // 'x', 'y' or 'd'iagonal
    if (axis == "x")
        which = 'x';
    else if (axis == "y")
        which = 'y';
    else if (axis == "diagonal")
        which = 'd';
    else if (axis == "smaller")
        which = aspect > 1 ? 'y' : 'x';
    else if (axis == "larger")
        which = aspect > 1 ? 'x' : 'y';
    if (which == 'x') return fov;
    if (which == 'y') return to_deg(2.0 * std::atan(std::tan(0.5 * to_rad(fov)) * aspect));
    if (which == 'd') {
        double diagonal = 2.0 * std::tan(0.5 * to_rad(fov));
        double width = diagonal / std::sqrt(1.0 + 1.0 / (aspect * aspect));
        return to_deg(2.0 * std::atan(0.5 * width));
    }
    throw std::invalid_argument("fov_axis must be one of x, y, diagonal, smaller, larger");
}

double focal_length_to_diagonal_fov(const std::string& text) {
    std::string s = text;
    if (s.size() >= 2 && s.compare(s.size() - 2, 2, "mm") == 0) s.resize(s.size() - 2);
    if (s.empty()) return -1.0;
    char* end = nullptr;
    double f = std::strtod(s.c_str(), &end);
    if (*end != '\0' || !(f > 0.0) || !std::isfinite(f)) return -1.0;
    // Diagonal of a 36 x 24 mm frame.
    return 2.0 * to_deg(std::atan(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / (2.0 * f)));
}

PerspectiveCamera::PerspectiveCamera(const Properties& props) : ProjectiveCamera(props) {
    if (props.has("fov") && props.has("focal_length"))
        props.fail_at("focal_length",
                      "specify either a field of view ('fov') or a focal length ('focal_length'), not both");
    double fov, aspect = double(film_->width()) / double(film_->height());
    std::string axis;
    if (props.has("fov")) {
        fov = props.get_float("fov");
        axis = props.get_string("fov_axis", "x");
    } else {
        if (props.has("fov_axis")) props.fail_at("fov_axis", "fov_axis needs a 'fov'");
        std::string f = props.get_string("focal_length", "50mm");
        fov = focal_length_to_diagonal_fov(f);
        if (fov < 0)
            props.fail_at("focal_length", "could not parse focal_length '{}' (expected e.g. '50mm')", f);
        axis = "diagonal";
    }
    const char* fov_param = props.has("fov") ? "fov" : "focal_length";
    if (!(fov > 0.0 && fov < 180.0))
        props.fail_at(fov_param, "the field of view must be in (0, 180) degrees, got {}", fov);
    double x_fov;
    try {
        x_fov = horizontal_fov(fov, axis, aspect);
    } catch (const std::invalid_argument& e) {
        props.fail_at("fov_axis", "{}, got '{}'", e.what(), axis);
    }
    if (!(x_fov > 0.0 && x_fov < 180.0))
        props.fail_at(fov_param, "the horizontal field of view must be in (0, 180) degrees, got {}", x_fov);
    x_fov_ = float(x_fov);
    // Mitsuba's principal point offset shifts the image plane, in fractions of the film size.
    principal_point_offset_ = {props.get_float("principal_point_offset_x", 0.f),
                               props.get_float("principal_point_offset_y", 0.f)};
    if (!std::isfinite(principal_point_offset_.x) || !std::isfinite(principal_point_offset_.y))
        props.fail_at("principal_point_offset_x", "principal point offsets must be finite");
    if (has_scale(to_world_))
        props.fail_at("to_world", "scale factors in the camera-to-world transform are not allowed");
    if (props.type() == "thinlens") read_lens(props);
    configure(&props);
}

PerspectiveCamera::PerspectiveCamera(std::shared_ptr<Film> film, const Transform& to_world, float x_fov_deg,
                                     float near_clip, float far_clip)
    : ProjectiveCamera(std::move(film), to_world, near_clip, far_clip), x_fov_(x_fov_deg) {
    if (!(x_fov_deg > 0.f && x_fov_deg < 180.f)) throw InputError({}, "perspective: fov must be in (0, 180)");
    configure(nullptr);
}

// thinlens: aperture_radius is required and positive (a zero aperture is the pinhole `perspective`);
// focus_distance defaults to far_clip, as for every Mitsuba projective camera.
void PerspectiveCamera::read_lens(const Properties& props) {
    aperture_radius_ = props.get_float("aperture_radius");
    focus_distance_ = props.get_float("focus_distance", far_clip_);
    if (!(aperture_radius_ > 0.f) || !std::isfinite(aperture_radius_))
        props.fail_at("aperture_radius", "thinlens: aperture_radius must be finite and > 0, got {}", aperture_radius_);
    if (!(focus_distance_ > 0.f) || !std::isfinite(focus_distance_))
        props.fail_at("focus_distance", "thinlens: focus_distance must be finite and > 0, got {}", focus_distance_);
}

void PerspectiveCamera::configure(const Properties*) {
    tan_half_x_ = float(std::tan(0.5 * to_rad(x_fov_)));
    origin_ = to_world_.apply_point(Point3f(0.f));
}

std::pair<Ray, Color3> PerspectiveCamera::sample_ray(Point2f film_uv, Point2f aperture) const {
    const Point2f uv = film_uv + principal_point_offset_;
    // Film u = 0 is camera +x (left), v = 0 is camera +y (up); the near plane spans
    // x in [-1, 1] * tan_half_x and y in [-1, 1] * tan_half_x / aspect.
    Vec3f local((1.f - 2.f * uv.x) * tan_half_x_, (1.f - 2.f * uv.y) * tan_half_x_ / aspect_, 1.f);
    Point3f lens(0.f);
    if (aperture_radius_ > 0.f) {
        // Thin lens: every ray through the lens point aims at the point of the focal plane (camera z =
        // focus_distance) that the pinhole ray through this film position reaches; weight 1 (Mitsuba).
        const Point2f disk = warp::square_to_uniform_disk_concentric(aperture);
        lens = Point3f(disk.x * aperture_radius_, disk.y * aperture_radius_, 0.f);
        local = local * focus_distance_ - Vec3f(lens.x, lens.y, 0.f);
    }
    local = normalize(local);
    float inv_z = 1.f / local.z;
    float near_t = near_clip_ * inv_z, far_t = far_clip_ * inv_z;
    Vec3f d = normalize(to_world_.apply_vector(local));
    const Point3f o = aperture_radius_ > 0.f ? to_world_.apply_point(lens) : origin_;
    return {Ray(o + d * near_t, d, far_t - near_t), Color3(1.f)};
}

// Inverse of sample_ray's film mapping. Importance per unit solid angle W(w) = 1 / (A cos³θ), A the
// film's area on the plane z = 1, so that splatting W L / pdf over W·H·spp light paths, each scaled by
// 1/spp, gives each pixel its mean radiance (Mitsuba 3's perspective importance).
SensorConnection PerspectiveCamera::project(const Vec3f& local) const {
    SensorConnection c;
    c.p = origin_;
    if (!(local.z > 0.f)) return c;
    const float px = local.x / local.z, py = local.y / local.z;
    const float u = 0.5f * (1.f - px / tan_half_x_) - principal_point_offset_.x;
    const float v = 0.5f * (1.f - py * aspect_ / tan_half_x_) - principal_point_offset_.y;
    if (!(u >= 0.f && u < 1.f && v >= 0.f && v < 1.f)) return c;
    c.film_pos = Point2f(u * float(film_->width()), v * float(film_->height()));
    const float cos_theta = local.z / norm(local);
    const float area = 4.f * tan_half_x_ * tan_half_x_ / aspect_;
    c.weight = 1.f / (area * cos_theta * cos_theta * cos_theta);
    return c;
}

SensorConnection PerspectiveCamera::connect(const Point3f& ref) const {
    const Vec3f local = to_world_.inverse().apply_vector(ref - origin_);
    if (!(local.z >= near_clip_ && local.z <= far_clip_)) {
        SensorConnection none;
        none.p = origin_;
        return none;
    }
    SensorConnection c = project(local);
    c.dist = norm(ref - origin_);
    c.d = (origin_ - ref) / c.dist;
    c.weight /= c.dist * c.dist;
    return c;
}

SensorConnection PerspectiveCamera::importance(const Vec3f& d) const {
    SensorConnection c = project(to_world_.inverse().apply_vector(d));
    c.d = -d;
    return c;
}

std::string PerspectiveCamera::to_string() const {
    return fmt::format("perspective[x_fov={:.4g}, near_clip={}, far_clip={}]", x_fov_, near_clip_, far_clip_);
}

}  // namespace volguide
