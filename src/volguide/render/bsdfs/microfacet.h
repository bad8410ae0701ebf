#pragma once
// Beckmann and GGX microfacet distributions (Walter et al. 2007) with Heitz-d'Eon visible normal
// sampling, following Mitsuba 3's MicrofacetDistribution: same parameters, clamping
// (alpha >= 1e-4), Smith approximation and sampling routines, so that renders agree.
#include <memory>
#include <utility>

#include "volguide/core/properties.h"
#include "volguide/core/vec.h"

namespace volguide {

class Texture;
struct SurfaceInteraction;

enum class MicrofacetType { Beckmann, GGX };

class MicrofacetDistribution {
  public:
    MicrofacetDistribution(MicrofacetType type, float alpha_u, float alpha_v, bool sample_visible = true)
        : type_(type),
          alpha_u_(std::max(alpha_u, 1e-4f)),
          alpha_v_(std::max(alpha_v, 1e-4f)),
          sample_visible_(sample_visible) {}

    MicrofacetType type() const { return type_; }
    float alpha_u() const { return alpha_u_; }
    float alpha_v() const { return alpha_v_; }
    bool sample_visible() const { return sample_visible_; }
    bool is_isotropic() const { return alpha_u_ == alpha_v_; }
    void scale_alpha(float s) {
        alpha_u_ *= s;
        alpha_v_ *= s;
    }

    // Normal distribution D(m) (projected area normalised: integral of D(m) cos(theta_m) = 1).
    float eval(const Vec3f& m) const;
    // Density of sample(): D(m) G1(wi, m) |wi.m| / cos(theta_i) (visible), else D(m) cos(theta_m).
    float pdf(const Vec3f& wi, const Vec3f& m) const;
    // A microfacet normal and its density; wi must lie in the upper hemisphere for visible sampling.
    std::pair<Vec3f, float> sample(const Vec3f& wi, Point2f u) const;
    // Smith's separable shadowing-masking.
    float G(const Vec3f& wi, const Vec3f& wo, const Vec3f& m) const {
        return smith_g1(wi, m) * smith_g1(wo, m);
    }
    float smith_g1(const Vec3f& v, const Vec3f& m) const;

  private:
    // Slope sample of the visible normals for alpha = 1 and the given incident elevation.
    Vec2f sample_visible_11(float cos_theta_i, Point2f u) const;

    MicrofacetType type_;
    float alpha_u_, alpha_v_;
    bool sample_visible_;
};

// Microfacet parameters of the rough BSDFs: `distribution` (beckmann | ggx, default beckmann),
// `alpha` or both `alpha_u` and `alpha_v` (textures, default alpha 0.1), `sample_visible`.
struct MicrofacetParams {
    MicrofacetType type = MicrofacetType::Beckmann;
    std::shared_ptr<Texture> alpha_u, alpha_v;
    bool sample_visible = true;
    bool anisotropic = false;
    // Constant roughness is looked up once instead of per query.
    bool constant = false;
    float const_alpha_u = 0.1f, const_alpha_v = 0.1f;

    static MicrofacetParams parse(const Properties& props);
    MicrofacetDistribution at(const SurfaceInteraction& si) const;
};

// Directional albedo of a rough dielectric interface seen from wi (Mitsuba's eval_reflectance /
// eval_transmittance), by Gauss-Legendre quadrature over visible-normal samples; used by
// roughplastic to precompute its transmittance table.
float rough_reflectance(const MicrofacetDistribution& distr, const Vec3f& wi, float eta);
float rough_transmittance(const MicrofacetDistribution& distr, const Vec3f& wi, float eta);

// Inverse error function (single precision, Giles 2010).
float erfinv(float x);

}  // namespace volguide
