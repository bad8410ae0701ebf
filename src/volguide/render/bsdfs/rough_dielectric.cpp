// `roughdielectric`: microfacet interface between two dielectrics (Walter et al. 2007), glossy
// reflection and refraction, lobes chosen by the Fresnel reflectance of the sampled microfacet.
#include "volguide/core/frame.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/fresnel.h"
#include "volguide/render/bsdfs/ior.h"
#include "volguide/render/bsdfs/microfacet.h"

namespace volguide {

namespace {

inline Vec3f mulsign(const Vec3f& v, float s) {
    return s >= 0.f ? v : -v;
}

class RoughDielectric final : public BSDF {
  public:
    explicit RoughDielectric(const Properties& props) {
        specular_reflectance_ = optional_texture(props, "specular_reflectance");
        specular_transmittance_ = optional_texture(props, "specular_transmittance");
        const float int_ior = lookup_ior(props, "int_ior", "bk7");
        const float ext_ior = lookup_ior(props, "ext_ior", "air");
        if (int_ior == ext_ior) props.fail_here("roughdielectric: the interior and exterior IOR must differ");
        eta_ = int_ior / ext_ior;
        inv_eta_ = ext_ior / int_ior;
        micro_ = MicrofacetParams::parse(props);
        flags_ = bsdf_flags::GlossyReflection | bsdf_flags::GlossyTransmission;
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si, float sample1,
                                         Point2f sample2) const override {
        const float cos_theta_i = si.wi.z;
        if (cos_theta_i == 0.f) return {BSDFSample{}, Color3(0.f)};  // perfectly grazing
        const MicrofacetDistribution distr = micro_.at(si);
        MicrofacetDistribution sample_distr = distr;
        // Walter et al.'s roughness widening; not needed with visible normal sampling.
        if (!distr.sample_visible()) sample_distr.scale_alpha(1.2f - 0.2f * std::sqrt(std::abs(cos_theta_i)));

        BSDFSample bs;
        auto [m, pdf_m] = sample_distr.sample(mulsign(si.wi, cos_theta_i), sample2);
        if (pdf_m == 0.f) return {BSDFSample{}, Color3(0.f)};
        const FresnelResult fr = fresnel_dielectric(dot(si.wi, m), eta_);

        const bool reflect = sample1 <= fr.F;
        Color3 weight(1.f);
        float dwh_dwo;
        if (reflect) {
            bs.wo = reflect_about(si.wi, m);
            bs.eta = 1.f;
            bs.sampled_flags = bsdf_flags::GlossyReflection;
            bs.pdf = pdf_m * fr.F;
            weight = eval_or_one(specular_reflectance_, si);
            dwh_dwo = 1.f / (4.f * dot(bs.wo, m));  // Jacobian of the half-vector mapping
        } else {
            bs.wo = refract_about(si.wi, m, fr.cos_theta_t, fr.eta_ti);
            bs.eta = fr.eta_it;
            bs.sampled_flags = bsdf_flags::GlossyTransmission;
            bs.pdf = pdf_m * (1.f - fr.F);
            weight = eval_or_one(specular_transmittance_, si);
            // Radiance is compressed into the smaller solid angle across the interface.
            if (ctx.mode == TransportMode::Radiance) weight *= sqr(fr.eta_ti);
            dwh_dwo = sqr(bs.eta) * dot(bs.wo, m) / sqr(dot(si.wi, m) + bs.eta * dot(bs.wo, m));
        }
        if (distr.sample_visible()) {
            weight *= distr.smith_g1(bs.wo, m);
        } else {
            // eval / pdf with the widened sampling distribution: D / pdf_m does not cancel.
            // (Mitsuba 3 omits this ratio, which biases its sample weights when
            // sample_visible = false; here the weight stays equal to eval / pdf.)
            weight *= distr.eval(m) * distr.G(si.wi, bs.wo, m) * dot(si.wi, m) / (cos_theta_i * pdf_m);
        }
        bs.pdf *= std::abs(dwh_dwo);
        if (!(bs.pdf > 0.f) || !std::isfinite(bs.pdf)) return {BSDFSample{}, Color3(0.f)};
        return {bs, weight};
    }

    Color3 eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const float cos_theta_i = si.wi.z, cos_theta_o = wo.z;
        if (cos_theta_i == 0.f) return Color3(0.f);
        const bool reflect = cos_theta_i * cos_theta_o > 0.f;
        const float eta = cos_theta_i > 0.f ? eta_ : inv_eta_;
        const float inv_eta = cos_theta_i > 0.f ? inv_eta_ : eta_;
        Vec3f m = normalize(si.wi + wo * (reflect ? 1.f : eta));
        m = mulsign(m, m.z);  // half-vector on the side of the macro-normal

        const MicrofacetDistribution distr = micro_.at(si);
        const float D = distr.eval(m);
        const float F = fresnel_dielectric(dot(si.wi, m), eta_).F;
        const float G = distr.G(si.wi, wo, m);
        if (reflect) {
            const float value = F * D * G / (4.f * std::abs(cos_theta_i));
            return eval_or_one(specular_reflectance_, si) * value;
        }
        const float scale = ctx.mode == TransportMode::Radiance ? sqr(inv_eta) : 1.f;
        const float value = std::abs(scale * (1.f - F) * D * G * eta * eta * dot(si.wi, m) * dot(wo, m) /
                                     (cos_theta_i * sqr(dot(si.wi, m) + eta * dot(wo, m))));
        return eval_or_one(specular_transmittance_, si) * value;
    }

    float pdf(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const float cos_theta_i = si.wi.z, cos_theta_o = wo.z;
        if (cos_theta_i == 0.f) return 0.f;
        const bool reflect = cos_theta_i * cos_theta_o > 0.f;
        const float eta = cos_theta_i > 0.f ? eta_ : inv_eta_;
        Vec3f m = normalize(si.wi + wo * (reflect ? 1.f : eta));
        m = mulsign(m, m.z);
        // Microsurface and macrosurface must agree on the sides (as smith_g1 does in eval/sample).
        if (!(dot(si.wi, m) * cos_theta_i > 0.f && dot(wo, m) * cos_theta_o > 0.f)) return 0.f;
        const float dwh_dwo = reflect ? 1.f / (4.f * dot(wo, m))
                                      : eta * eta * dot(wo, m) / sqr(dot(si.wi, m) + eta * dot(wo, m));
        MicrofacetDistribution sample_distr = micro_.at(si);
        if (!sample_distr.sample_visible())
            sample_distr.scale_alpha(1.2f - 0.2f * std::sqrt(std::abs(cos_theta_i)));
        float prob = sample_distr.pdf(mulsign(si.wi, cos_theta_i), m);
        const float F = fresnel_dielectric(dot(si.wi, m), eta_).F;
        prob *= reflect ? F : 1.f - F;
        const float result = prob * std::abs(dwh_dwo);
        return std::isfinite(result) ? result : 0.f;
    }

    std::string to_string() const override { return "RoughDielectric[]"; }

  private:
    float eta_, inv_eta_;
    MicrofacetParams micro_;
    std::shared_ptr<Texture> specular_reflectance_, specular_transmittance_;
};

}  // namespace

ObjectPtr make_rough_dielectric_bsdf(const Properties& props) {
    return std::make_shared<RoughDielectric>(props);
}

}  // namespace volguide
