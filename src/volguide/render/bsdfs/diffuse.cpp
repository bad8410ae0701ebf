// `diffuse`: one-sided Lambertian reflector (black when wi or wo is below the surface).
#include "volguide/core/warp.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"

namespace volguide {

namespace {

class Diffuse final : public BSDF {
  public:
    explicit Diffuse(const Properties& props) {
        reflectance_ = nonnegative_texture(props, "reflectance", Color3(0.5f));
        flags_ = bsdf_flags::DiffuseReflection;
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext&, const SurfaceInteraction& si, float,
                                         Point2f sample2) const override {
        BSDFSample bs;
        if (si.wi.z <= 0.f) return {bs, Color3(0.f)};
        bs.wo = warp::square_to_cosine_hemisphere(sample2);
        bs.pdf = warp::square_to_cosine_hemisphere_pdf(bs.wo);
        bs.sampled_flags = bsdf_flags::DiffuseReflection;
        if (bs.pdf <= 0.f) return {BSDFSample{}, Color3(0.f)};
        return {bs, reflectance_->eval(si)};
    }

    Color3 eval(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        if (si.wi.z <= 0.f || wo.z <= 0.f) return Color3(0.f);
        return reflectance_->eval(si) * (InvPi * wo.z);
    }

    float pdf(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        if (si.wi.z <= 0.f || wo.z <= 0.f) return 0.f;
        return warp::square_to_cosine_hemisphere_pdf(wo);
    }

    std::string to_string() const override { return "Diffuse[]"; }

  private:
    std::shared_ptr<Texture> reflectance_;
};

}  // namespace

ObjectPtr make_diffuse_bsdf(const Properties& props) {
    return std::make_shared<Diffuse>(props);
}

}  // namespace volguide
