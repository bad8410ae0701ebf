// `conductor`: smooth metal, a perfect specular reflection weighted by the conductor Fresnel term.
// One-sided: black from below.
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/conductor_ior.h"
#include "volguide/render/bsdfs/fresnel.h"

namespace volguide {

namespace {

class SmoothConductor final : public BSDF {
  public:
    explicit SmoothConductor(const Properties& props) {
        specular_reflectance_ = nonnegative_texture(props, "specular_reflectance", Color3(1.f));
        ior_ = ConductorIor::parse(props);
        flags_ = bsdf_flags::DeltaReflection;
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext&, const SurfaceInteraction& si, float,
                                         Point2f) const override {
        const float cos_theta_i = si.wi.z;
        if (cos_theta_i <= 0.f) return {BSDFSample{}, Color3(0.f)};
        BSDFSample bs;
        bs.wo = reflect_local(si.wi);
        bs.pdf = 1.f;
        bs.eta = 1.f;
        bs.sampled_flags = bsdf_flags::DeltaReflection;
        const Color3 F = fresnel_conductor(cos_theta_i, ior_.eta->eval(si), ior_.k->eval(si));
        return {bs, specular_reflectance_->eval(si) * F};
    }

    Color3 eval(const BSDFContext&, const SurfaceInteraction&, const Vec3f&) const override {
        return Color3(0.f);
    }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3f&) const override { return 0.f; }
    std::string to_string() const override { return "SmoothConductor[]"; }

  private:
    std::shared_ptr<Texture> specular_reflectance_;
    ConductorIor ior_;
};

}  // namespace

ObjectPtr make_conductor_bsdf(const Properties& props) {
    return std::make_shared<SmoothConductor>(props);
}

}  // namespace volguide
