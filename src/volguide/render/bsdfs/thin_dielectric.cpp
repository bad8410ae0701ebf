// `thindielectric`: a thin slab (e.g. a window pane). Reflection R' = R + T R T + ... = 2R / (1 + R)
// sums the internal bounces; the rest passes straight through (a Null lobe: wo = -wi, no refraction).
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/fresnel.h"
#include "volguide/render/bsdfs/ior.h"

namespace volguide {

namespace {

class ThinDielectric final : public BSDF {
  public:
    explicit ThinDielectric(const Properties& props) {
        const float int_ior = lookup_ior(props, "int_ior", "bk7");
        const float ext_ior = lookup_ior(props, "ext_ior", "air");
        eta_ = int_ior / ext_ior;
        specular_reflectance_ = optional_texture(props, "specular_reflectance");
        specular_transmittance_ = optional_texture(props, "specular_transmittance");
        flags_ = bsdf_flags::DeltaReflection | bsdf_flags::Null;
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext&, const SurfaceInteraction& si, float sample1,
                                         Point2f) const override {
        const float r = reflectance(si);
        BSDFSample bs;
        bs.eta = 1.f;
        if (sample1 <= r) {
            bs.wo = reflect_local(si.wi);
            bs.pdf = r;
            bs.sampled_flags = bsdf_flags::DeltaReflection;
            return {bs, eval_or_one(specular_reflectance_, si)};
        }
        bs.wo = -si.wi;
        bs.pdf = 1.f - r;
        bs.sampled_flags = bsdf_flags::Null;
        return {bs, eval_or_one(specular_transmittance_, si)};
    }

    Color3 eval(const BSDFContext&, const SurfaceInteraction&, const Vec3f&) const override {
        return Color3(0.f);
    }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3f&) const override { return 0.f; }
    Color3 eval_null_transmission(const SurfaceInteraction& si) const override {
        return eval_or_one(specular_transmittance_, si) * (1.f - reflectance(si));
    }
    std::string to_string() const override { return "ThinDielectric[]"; }

  private:
    float reflectance(const SurfaceInteraction& si) const {
        const float r = fresnel_dielectric(std::abs(si.wi.z), eta_).F;
        return r * 2.f / (1.f + r);
    }

    float eta_;
    std::shared_ptr<Texture> specular_reflectance_, specular_transmittance_;
};

}  // namespace

ObjectPtr make_thin_dielectric_bsdf(const Properties& props) {
    return std::make_shared<ThinDielectric>(props);
}

}  // namespace volguide
