#pragma once
// Warps from [0,1)^2 to common domains, each with its pdf (w.r.t. area or solid angle).
#include "volguide/core/frame.h"
#include "volguide/core/vec.h"

namespace volguide::warp {

// Shirley-Chiu concentric map to the unit disk.
inline Point2f square_to_uniform_disk_concentric(Point2f u) {
    float x = 2.f * u.x - 1.f, y = 2.f * u.y - 1.f;
    if (x == 0.f && y == 0.f) return {0.f, 0.f};
    float r, phi;
    if (std::abs(x) > std::abs(y)) {
        r = x;
        phi = (Pi / 4.f) * (y / x);
    } else {
        r = y;
        phi = (Pi / 2.f) - (Pi / 4.f) * (x / y);
    }
    return {r * std::cos(phi), r * std::sin(phi)};
}
inline float square_to_uniform_disk_pdf() { return InvPi; }

inline Vec3f square_to_cosine_hemisphere(Point2f u) {
    Point2f d = square_to_uniform_disk_concentric(u);
    return {d.x, d.y, safe_sqrt(1.f - d.x * d.x - d.y * d.y)};
}
inline float square_to_cosine_hemisphere_pdf(const Vec3f& v) { return v.z > 0.f ? v.z * InvPi : 0.f; }

inline Vec3f square_to_uniform_sphere(Point2f u) {
    float z = 1.f - 2.f * u.x;
    float r = safe_sqrt(1.f - z * z);
    float phi = 2.f * Pi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float square_to_uniform_sphere_pdf() { return InvFourPi; }

inline Vec3f square_to_uniform_hemisphere(Point2f u) {
    float z = u.x;
    float r = safe_sqrt(1.f - z * z);
    float phi = 2.f * Pi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float square_to_uniform_hemisphere_pdf(const Vec3f& v) { return v.z >= 0.f ? InvTwoPi : 0.f; }

// Uniform in the cone of directions with cos(theta) >= cos_cutoff about +z.
inline Vec3f square_to_uniform_cone(Point2f u, float cos_cutoff) {
    float cos_theta = (1.f - u.x) + u.x * cos_cutoff;
    float sin_theta = safe_sqrt(1.f - cos_theta * cos_theta);
    float phi = 2.f * Pi * u.y;
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}
inline float square_to_uniform_cone_pdf(const Vec3f& v, float cos_cutoff) {
    return v.z >= cos_cutoff ? InvTwoPi / (1.f - cos_cutoff) : 0.f;
}

// Uniform barycentrics (b1, b2) on a triangle; b0 = 1 - b1 - b2.
inline Point2f square_to_uniform_triangle(Point2f u) {
    float t = safe_sqrt(1.f - u.x);
    return {1.f - t, t * u.y};
}

}  // namespace volguide::warp
