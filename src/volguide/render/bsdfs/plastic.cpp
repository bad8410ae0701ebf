// `plastic`: smooth dielectric coating over a diffuse base (Mitsuba's model): a delta specular
// reflection plus a diffuse lobe attenuated by Fresnel transmission in and out, with internal
// reflections approximated through the diffuse Fresnel reflectance fdr_int.
#include "volguide/core/warp.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/fresnel.h"
#include "volguide/render/bsdfs/ior.h"

namespace volguide {

namespace {

class SmoothPlastic final : public BSDF {
  public:
    explicit SmoothPlastic(const Properties& props) {
        const float int_ior = lookup_ior(props, "int_ior", "polypropylene");
        const float ext_ior = lookup_ior(props, "ext_ior", "air");
        eta_ = int_ior / ext_ior;
        diffuse_reflectance_ = nonnegative_texture(props, "diffuse_reflectance", Color3(0.5f));
        specular_reflectance_ = optional_texture(props, "specular_reflectance");
        nonlinear_ = props.get_bool("nonlinear", false);
        inv_eta_2_ = 1.f / (eta_ * eta_);
        fdr_int_ = fresnel_diffuse_reflectance(1.f / eta_);
        // Steer samples by the mean albedos of the two layers.
        const float d_mean = scalar_mean(diffuse_reflectance_), s_mean = scalar_mean(specular_reflectance_);
        specular_sampling_weight_ = s_mean / (d_mean + s_mean);
        flags_ = bsdf_flags::DeltaReflection | bsdf_flags::DiffuseReflection;
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext&, const SurfaceInteraction& si, float sample1,
                                         Point2f sample2) const override {
        const float cos_theta_i = si.wi.z;
        if (cos_theta_i <= 0.f) return {BSDFSample{}, Color3(0.f)};
        const float f_i = fresnel_dielectric(cos_theta_i, eta_).F;
        const float prob_specular = specular_probability(f_i), prob_diffuse = 1.f - prob_specular;
        BSDFSample bs;
        bs.eta = 1.f;
        if (sample1 < prob_specular) {
            bs.wo = reflect_local(si.wi);
            bs.pdf = prob_specular;
            bs.sampled_flags = bsdf_flags::DeltaReflection;
            return {bs, eval_or_one(specular_reflectance_, si) * (f_i / prob_specular)};
        }
        bs.wo = warp::square_to_cosine_hemisphere(sample2);
        bs.pdf = prob_diffuse * warp::square_to_cosine_hemisphere_pdf(bs.wo);
        bs.sampled_flags = bsdf_flags::DiffuseReflection;
        if (!(bs.pdf > 0.f)) return {BSDFSample{}, Color3(0.f)};
        const float f_o = fresnel_dielectric(bs.wo.z, eta_).F;
        const Color3 value = diffuse(si) * (inv_eta_2_ * (1.f - f_i) * (1.f - f_o) / prob_diffuse);
        return {bs, value};
    }

    Color3 eval(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const float cos_theta_i = si.wi.z, cos_theta_o = wo.z;
        if (!(cos_theta_i > 0.f && cos_theta_o > 0.f)) return Color3(0.f);
        const float f_i = fresnel_dielectric(cos_theta_i, eta_).F,
                    f_o = fresnel_dielectric(cos_theta_o, eta_).F;
        return diffuse(si) *
               (warp::square_to_cosine_hemisphere_pdf(wo) * inv_eta_2_ * (1.f - f_i) * (1.f - f_o));
    }

    float pdf(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const float cos_theta_i = si.wi.z, cos_theta_o = wo.z;
        if (!(cos_theta_i > 0.f && cos_theta_o > 0.f)) return 0.f;
        const float f_i = fresnel_dielectric(cos_theta_i, eta_).F;
        return warp::square_to_cosine_hemisphere_pdf(wo) * (1.f - specular_probability(f_i));
    }

    std::string to_string() const override { return "SmoothPlastic[]"; }

  private:
    float specular_probability(float f_i) const {
        const float ps = f_i * specular_sampling_weight_,
                    pd = (1.f - f_i) * (1.f - specular_sampling_weight_);
        return ps / (ps + pd);
    }
    // Diffuse base including the internal-scattering normalisation 1 / (1 - fdr_int [* albedo]).
    Color3 diffuse(const SurfaceInteraction& si) const {
        const Color3 d = diffuse_reflectance_->eval(si);
        const Color3 denom = nonlinear_ ? Color3(1.f) - d * fdr_int_ : Color3(1.f - fdr_int_);
        return d / denom;
    }

    float eta_, inv_eta_2_, fdr_int_, specular_sampling_weight_;
    bool nonlinear_;
    std::shared_ptr<Texture> diffuse_reflectance_, specular_reflectance_;
};

}  // namespace

ObjectPtr make_plastic_bsdf(const Properties& props) {
    return std::make_shared<SmoothPlastic>(props);
}

}  // namespace volguide
