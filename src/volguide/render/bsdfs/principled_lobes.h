#pragma once
// Pieces shared by `principled` and `principledthin` (Mitsuba 3's principled BSDFs, after Burley's
// "Physically Based Shading at Disney", 2012/2015): their common textured parameters, the Schlick
// Fresnel terms, the GTR1 clearcoat distribution, the GGX roughness mapping and the diffuse/retro/
// fake-subsurface and sheen terms. Formulas: docs/theory.md §18.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "volguide/core/color.h"
#include "volguide/core/properties.h"
#include "volguide/core/vec.h"
#include "volguide/geometry/interaction.h"
#include "volguide/render/bsdfs/microfacet.h"
#include "volguide/render/texture.h"

namespace volguide::principled {

// v or -v so that its z has the sign of s (Mitsuba's mulsign: +0 counts as positive).
inline Vec3f flip_to_sign(const Vec3f& v, float s) {
    return s >= 0.f ? v : -v;
}

// (1 - cos)^5 with cos clamped to [0, 1].
inline float schlick_weight(float cos_i) {
    const float m = std::clamp(1.f - cos_i, 0.f, 1.f);
    return (m * m) * (m * m) * m;
}

// Normal-incidence reflectance of a dielectric of relative IOR eta.
inline float schlick_r0(float eta) {
    const float r = (eta - 1.f) / (eta + 1.f);
    return r * r;
}

// The Schlick weight of Mitsuba's calc_schlick: (1 - cos)^5 of the incident cosine when the light
// enters the denser side, else of the refracted cosine (0 past total internal reflection).
float schlick_fresnel_weight(float cos_theta_i, float eta);

inline float schlick_fresnel(float r0, float cos_theta_i, float eta) {
    const float w = schlick_fresnel_weight(cos_theta_i, eta);
    return r0 + (1.f - r0) * w;
}
inline Color3 schlick_fresnel(const Color3& r0, float cos_theta_i, float eta) {
    const float w = schlick_fresnel_weight(cos_theta_i, eta);
    return r0 + (Color3(1.f) - r0) * w;
}

// base_color normalised by its luminance (white for a black base colour): the tint colour.
inline Color3 tint_color(const Color3& base_color) {
    const float lum = base_color.luminance();
    return lum > 0.f ? base_color / lum : Color3(1.f);
}

// GGX of the main specular lobe: alpha = roughness^2, stretched by `anisotropic` (Burley 2012),
// both at least 0.001. Without an `anisotropic` parameter the lobe is isotropic.
MicrofacetDistribution main_distribution(float anisotropic, float roughness, bool has_anisotropic);

// Whether wi and wo lie on the sides of the microfacet m that reflection (or refraction) needs,
// m being oriented towards the side of wi given by cos_theta_i.
bool microfacet_compatible(const Vec3f& m, const Vec3f& wi, const Vec3f& wo, float cos_theta_i, bool reflection);

// Burley's GTR1 ("Berry") distribution of the clearcoat lobe, isotropic; sampled by its normals
// weighted with cos(theta_m) (no visible-normal sampling, as Mitsuba).
class Gtr1 {
  public:
    explicit Gtr1(float alpha) : alpha_(alpha) {}
    float eval(const Vec3f& m) const;
    float pdf(const Vec3f& m) const { return m.z < 0.f ? 0.f : m.z * eval(m); }
    Vec3f sample(Point2f u) const;

  private:
    float alpha_;
};

// Smith's G1 of an isotropic GGX of roughness alpha (the clearcoat's fixed 0.25), zero when v sees
// the back of wh.
float smith_ggx1(const Vec3f& v, const Vec3f& wh, float alpha);

// The parameters both plugins take with the same name and meaning. Mitsuba switches a lobe's code
// on when its parameter is given and is not the float 0 (`has_*`); absent weights are 0.
struct CommonParams {
    std::shared_ptr<Texture> base_color, roughness, anisotropic, spec_trans, sheen, sheen_tint, flatness, spec_tint;
    bool has_anisotropic = false, has_spec_trans = false, has_sheen = false, has_sheen_tint = false,
         has_flatness = false, has_spec_tint = false;

    static CommonParams parse(const Properties& props);
};

// CommonParams looked up at one surface point.
struct CommonValues {
    Color3 base_color;
    float roughness = 0.f, anisotropic = 0.f, spec_trans = 0.f, sheen = 0.f, sheen_tint = 0.f, flatness = 0.f,
          spec_tint = 0.f;

    static CommonValues at(const CommonParams& p, const SurfaceInteraction& si);
};

// Mitsuba's get_flag: given, and not the float 0.
bool has_flag(const Properties& props, const std::string& name);

// A sampling rate: a non-negative finite float, default 1.
float sampling_rate(const Properties& props, const std::string& name);

// Diffuse + retro-reflection (or its lerp towards the fake subsurface term by `flatness`), times
// base_color / pi * |cos_theta_o|; cos_theta_d = wh . wo. Without the lobe's weight.
Color3 diffuse_term(const CommonValues& v, bool has_flatness, float cos_theta_i, float cos_theta_o,
                    float cos_theta_d);

// Sheen * Schlick(cos_theta_d) * (tinted colour) * |cos_theta_o|, without the lobe's weight.
Color3 sheen_term(const CommonValues& v, bool has_sheen_tint, float cos_theta_o, float cos_theta_d);

}  // namespace volguide::principled
