#pragma once
// Fresnel equations and specular reflection/refraction in the local shading frame (normal = +z),
// with Mitsuba 3's conventions: eta = interior IOR / exterior IOR, and a negative cos(theta_i)
// means the incident direction is inside.
#include "volguide/core/color.h"
#include "volguide/core/vec.h"

namespace volguide {

struct FresnelResult {
    float F;            // unpolarized reflectance
    float cos_theta_t;  // signed cosine of the transmitted direction (opposite side to wi)
    float eta_it;       // relative IOR in the direction of travel
    float eta_ti;       // its reciprocal: scale of the tangential components of the refracted direction
};

// Dielectric interface. Total internal reflection gives F = 1; eta == 1 gives F = 0.
FresnelResult fresnel_dielectric(float cos_theta_i, float eta);

// Conductor with complex relative IOR eta + i k (light arriving from outside), per channel.
float fresnel_conductor(float cos_theta_i, float eta, float k);
Color3 fresnel_conductor(float cos_theta_i, const Color3& eta, const Color3& k);

// Hemispherically averaged (diffuse) Fresnel reflectance of a dielectric, Mitsuba's fitted
// approximation (Egan-Hilgeman for eta < 1, d'Eon-Irving otherwise).
float fresnel_diffuse_reflectance(float eta);

// Mirror reflection about +z.
inline Vec3f reflect_local(const Vec3f& wi) {
    return {-wi.x, -wi.y, wi.z};
}
// Mirror reflection about the normal m.
inline Vec3f reflect_about(const Vec3f& wi, const Vec3f& m) {
    return m * (2.f * dot(wi, m)) - wi;
}
// Refraction about +z, with cos_theta_t and eta_ti from fresnel_dielectric().
inline Vec3f refract_local(const Vec3f& wi, float cos_theta_t, float eta_ti) {
    return {-eta_ti * wi.x, -eta_ti * wi.y, cos_theta_t};
}
// Refraction about the microfacet normal m.
inline Vec3f refract_about(const Vec3f& wi, const Vec3f& m, float cos_theta_t, float eta_ti) {
    return m * (dot(wi, m) * eta_ti + cos_theta_t) - wi * eta_ti;
}

}  // namespace volguide
