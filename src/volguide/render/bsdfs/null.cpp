// `null`: an invisible, index-matched boundary (e.g. the surface enclosing a medium). Sampling
// passes straight through with weight 1; eval and pdf are zero.
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"

namespace volguide {

namespace {

class NullBSDF final : public BSDF {
  public:
    explicit NullBSDF(const Properties&) { flags_ = bsdf_flags::Null; }

    std::pair<BSDFSample, Color3> sample(const BSDFContext&, const SurfaceInteraction& si, float,
                                         Point2f) const override {
        BSDFSample bs;
        bs.wo = -si.wi;
        bs.pdf = 1.f;
        bs.eta = 1.f;
        bs.sampled_flags = bsdf_flags::Null;
        return {bs, Color3(1.f)};
    }
    Color3 eval(const BSDFContext&, const SurfaceInteraction&, const Vec3f&) const override {
        return Color3(0.f);
    }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3f&) const override { return 0.f; }
    Color3 eval_null_transmission(const SurfaceInteraction&) const override { return Color3(1.f); }
    std::string to_string() const override { return "Null[]"; }
};

}  // namespace

ObjectPtr make_null_bsdf(const Properties& props) {
    return std::make_shared<NullBSDF>(props);
}

}  // namespace volguide
