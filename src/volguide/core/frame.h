#pragma once
// Orthonormal frame. Local coordinates put the normal on +z (Mitsuba's convention), so
// cos(theta) of a local direction is its z component.
#include "volguide/core/vec.h"

namespace volguide {

// Builds s, t perpendicular to unit n (Duff et al. 2017, branchless).
inline void coordinate_system(const Vec3f& n, Vec3f& s, Vec3f& t) {
    float sign = std::copysign(1.f, n.z);
    float a = -1.f / (sign + n.z);
    float b = n.x * n.y * a;
    s = {1.f + sign * n.x * n.x * a, sign * b, -sign * n.x};
    t = {b, sign + n.y * n.y * a, -n.y};
}

struct Frame {
    Vec3f s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};
    Frame() = default;
    explicit Frame(const Vec3f& normal) : n(normal) { coordinate_system(n, s, t); }
    Frame(const Vec3f& s_, const Vec3f& t_, const Vec3f& n_) : s(s_), t(t_), n(n_) {}
    Vec3f to_local(const Vec3f& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3f to_world(const Vec3f& v) const { return s * v.x + t * v.y + n * v.z; }

    static float cos_theta(const Vec3f& v) { return v.z; }
    static float cos_theta_2(const Vec3f& v) { return v.z * v.z; }
    static float sin_theta_2(const Vec3f& v) { return std::max(0.f, 1.f - v.z * v.z); }
    static float sin_theta(const Vec3f& v) { return std::sqrt(sin_theta_2(v)); }
    static float tan_theta(const Vec3f& v) { return sin_theta(v) / v.z; }
    static float tan_theta_2(const Vec3f& v) { return sin_theta_2(v) / (v.z * v.z); }
};

}  // namespace volguide
