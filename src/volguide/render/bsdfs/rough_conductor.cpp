// `roughconductor`: microfacet metal (Beckmann or GGX), conductor Fresnel, one-sided.
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/conductor_ior.h"
#include "volguide/render/bsdfs/fresnel.h"
#include "volguide/render/bsdfs/microfacet.h"

namespace volguide {

namespace {

class RoughConductor final : public BSDF {
  public:
    explicit RoughConductor(const Properties& props) {
        ior_ = ConductorIor::parse(props);
        micro_ = MicrofacetParams::parse(props);
        specular_reflectance_ = optional_texture(props, "specular_reflectance");
        flags_ = bsdf_flags::GlossyReflection;
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext&, const SurfaceInteraction& si, float,
                                         Point2f sample2) const override {
        const float cos_theta_i = si.wi.z;
        if (cos_theta_i <= 0.f) return {BSDFSample{}, Color3(0.f)};
        const MicrofacetDistribution distr = micro_.at(si);
        auto [m, pdf_m] = distr.sample(si.wi, sample2);
        BSDFSample bs;
        bs.wo = reflect_about(si.wi, m);
        bs.eta = 1.f;
        bs.sampled_flags = bsdf_flags::GlossyReflection;
        if (pdf_m == 0.f || bs.wo.z <= 0.f) return {BSDFSample{}, Color3(0.f)};
        float weight = distr.sample_visible()
                           ? distr.smith_g1(bs.wo, m)
                           : distr.G(si.wi, bs.wo, m) * dot(si.wi, m) / (cos_theta_i * m.z);
        bs.pdf = pdf_m / (4.f * dot(bs.wo, m));
        const Color3 F = fresnel_conductor(dot(si.wi, m), ior_.eta->eval(si), ior_.k->eval(si));
        return {bs, eval_or_one(specular_reflectance_, si) * F * weight};
    }

    Color3 eval(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const float cos_theta_i = si.wi.z, cos_theta_o = wo.z;
        if (!(cos_theta_i > 0.f && cos_theta_o > 0.f)) return Color3(0.f);
        const Vec3f h = normalize(wo + si.wi);
        const MicrofacetDistribution distr = micro_.at(si);
        const float D = distr.eval(h);
        if (D == 0.f) return Color3(0.f);
        const float G = distr.G(si.wi, wo, h);
        const float value = D * G / (4.f * cos_theta_i);
        const Color3 F = fresnel_conductor(dot(si.wi, h), ior_.eta->eval(si), ior_.k->eval(si));
        return eval_or_one(specular_reflectance_, si) * F * value;
    }

    float pdf(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const float cos_theta_i = si.wi.z, cos_theta_o = wo.z;
        const Vec3f m = normalize(wo + si.wi);
        if (!(cos_theta_i > 0.f && cos_theta_o > 0.f && dot(si.wi, m) > 0.f && dot(wo, m) > 0.f)) return 0.f;
        const MicrofacetDistribution distr = micro_.at(si);
        if (distr.sample_visible()) return distr.eval(m) * distr.smith_g1(si.wi, m) / (4.f * cos_theta_i);
        return distr.pdf(si.wi, m) / (4.f * dot(wo, m));
    }

    std::string to_string() const override { return "RoughConductor[]"; }

  private:
    ConductorIor ior_;
    MicrofacetParams micro_;
    std::shared_ptr<Texture> specular_reflectance_;
};

}  // namespace

ObjectPtr make_rough_conductor_bsdf(const Properties& props) {
    return std::make_shared<RoughConductor>(props);
}

}  // namespace volguide
