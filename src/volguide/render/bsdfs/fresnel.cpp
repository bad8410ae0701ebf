#include "volguide/render/bsdfs/fresnel.h"

#include <cmath>

#include "volguide/core/math.h"

namespace volguide {

FresnelResult fresnel_dielectric(float cos_theta_i, float eta) {
    const bool outside = cos_theta_i >= 0.f;
    const float eta_it = outside ? eta : 1.f / eta;
    const float eta_ti = outside ? 1.f / eta : eta;
    // Snell: squared cosine of the transmitted direction (negative under total internal reflection).
    const float cos_t_sqr = 1.f - (1.f - cos_theta_i * cos_theta_i) * eta_ti * eta_ti;
    const float ci = std::abs(cos_theta_i);
    const float ct = safe_sqrt(cos_t_sqr);

    float F;
    if (eta == 1.f) {
        F = 0.f;
    } else if (ci == 0.f) {
        F = 1.f;
    } else {
        // Amplitudes of the s- and p-polarized reflected waves; under total internal reflection
        // ct = 0 and both are +-1, giving F = 1.
        const float a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
        const float a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
        F = 0.5f * (a_s * a_s + a_p * a_p);
    }
    // The transmitted direction lies on the other side of the interface.
    const float cos_theta_t = outside ? -ct : ct;
    return {F, cos_theta_t, eta_it, eta_ti};
}

float fresnel_conductor(float cos_theta_i, float eta, float k) {
    // Exact unpolarized reflectance of an absorbing medium (Moeller, Optics), as Mitsuba.
    const float c2 = cos_theta_i * cos_theta_i, s2 = 1.f - c2, s4 = s2 * s2;
    const float t1 = eta * eta - k * k - s2;
    const float a2pb2 = safe_sqrt(t1 * t1 + 4.f * k * k * eta * eta);
    const float a = safe_sqrt(0.5f * (a2pb2 + t1));
    const float term1 = a2pb2 + c2, term2 = 2.f * cos_theta_i * a;
    const float r_s = (term1 - term2) / (term1 + term2);
    const float term3 = a2pb2 * c2 + s4, term4 = term2 * s2;
    const float r_p = r_s * (term3 - term4) / (term3 + term4);
    return 0.5f * (r_s + r_p);
}

Color3 fresnel_conductor(float cos_theta_i, const Color3& eta, const Color3& k) {
    return {fresnel_conductor(cos_theta_i, eta.r, k.r), fresnel_conductor(cos_theta_i, eta.g, k.g),
            fresnel_conductor(cos_theta_i, eta.b, k.b)};
}

float fresnel_diffuse_reflectance(float eta) {
    if (eta < 1.f) {
        // Egan and Hilgeman (1973) fit.
        return -1.4399f * eta * eta + 0.7099f * eta + 0.6681f + 0.0636f / eta;
    }
    // d'Eon and Irving (2011) fit.
    const float i1 = 1.f / eta, i2 = i1 * i1, i3 = i2 * i1, i4 = i3 * i1, i5 = i4 * i1;
    return 0.919317f - 3.4793f * i1 + 6.75335f * i2 - 7.80989f * i3 + 4.98554f * i4 - 1.36881f * i5;
}

}  // namespace volguide
