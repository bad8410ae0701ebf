// `dielectric`: smooth interface between two dielectrics (delta reflection + delta refraction),
// lobes chosen in proportion to the Fresnel reflectance. eta = int_ior / ext_ior; the exterior
// is the side the normal points to.
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/fresnel.h"
#include "volguide/render/bsdfs/ior.h"

namespace volguide {

namespace {

class SmoothDielectric final : public BSDF {
  public:
    explicit SmoothDielectric(const Properties& props) {
        const float int_ior = lookup_ior(props, "int_ior", "bk7");
        const float ext_ior = lookup_ior(props, "ext_ior", "air");
        eta_ = int_ior / ext_ior;
        specular_reflectance_ = optional_texture(props, "specular_reflectance");
        specular_transmittance_ = optional_texture(props, "specular_transmittance");
        flags_ = bsdf_flags::DeltaReflection | bsdf_flags::DeltaTransmission;
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si, float sample1,
                                         Point2f) const override {
        const FresnelResult fr = fresnel_dielectric(si.wi.z, eta_);
        BSDFSample bs;
        const bool reflect = sample1 <= fr.F;
        if (reflect) {
            bs.wo = reflect_local(si.wi);
            bs.pdf = fr.F;
            bs.eta = 1.f;
            bs.sampled_flags = bsdf_flags::DeltaReflection;
            return {bs, eval_or_one(specular_reflectance_, si)};
        }
        bs.wo = refract_local(si.wi, fr.cos_theta_t, fr.eta_ti);
        bs.pdf = 1.f - fr.F;
        bs.eta = fr.eta_it;
        bs.sampled_flags = bsdf_flags::DeltaTransmission;
        Color3 weight = eval_or_one(specular_transmittance_, si);
        // Radiance is scaled by the solid angle compression across the interface (not importance).
        if (ctx.mode == TransportMode::Radiance) weight *= sqr(fr.eta_ti);
        return {bs, weight};
    }

    Color3 eval(const BSDFContext&, const SurfaceInteraction&, const Vec3f&) const override {
        return Color3(0.f);
    }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3f&) const override { return 0.f; }
    std::string to_string() const override { return "SmoothDielectric[]"; }

  private:
    float eta_;
    std::shared_ptr<Texture> specular_reflectance_, specular_transmittance_;
};

}  // namespace

ObjectPtr make_dielectric_bsdf(const Properties& props) {
    return std::make_shared<SmoothDielectric>(props);
}

}  // namespace volguide
