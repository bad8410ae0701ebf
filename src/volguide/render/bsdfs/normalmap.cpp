// `normalmap` (Mitsuba 3): a nested BSDF evaluated in a shading frame whose normal is read from the
// `normalmap` texture (RGB in [0, 1] → 2·rgb − 1, in the surface's shading frame; usually a raw
// bitmap) and whose tangent is dp_du made orthogonal to it (Gram-Schmidt). wi and wo are carried into
// that frame; a direction on opposite sides of the two frames' surfaces gives zero, as Mitsuba.
#include "volguide/core/frame.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"

namespace volguide {

namespace {

class NormalMapBSDF final : public BSDF {
  public:
    explicit NormalMapBSDF(const Properties& props) : normals_(texture_param(props, "normalmap")) {
        auto children = props.children("bsdf");
        if (children.size() != 1)
            props.fail_here("normalmap: exactly one nested BSDF is required, got {}", children.size());
        nested_ = std::dynamic_pointer_cast<BSDF>(std::get<ObjectPtr>(children[0]->value));
        if (!nested_) props.fail_at(children[0]->name, "normalmap: nested object is not a BSDF");
        flags_ = nested_->flags();
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si, float sample1,
                                         Point2f sample2) const override {
        const SurfaceInteraction perturbed = perturb(si);
        auto [bs, weight] = nested_->sample(ctx, perturbed, sample1, sample2);
        if (weight.is_black()) return {bs, weight};
        const Vec3f wo_world = perturbed.to_world(bs.wo);
        const Vec3f wo = si.to_local(wo_world);
        if (!(bs.wo.z * wo.z > 0.f)) return {BSDFSample{}, Color3(0.f)};
        bs.wo = wo;
        return {bs, weight};
    }
    Color3 eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const SurfaceInteraction perturbed = perturb(si);
        const Vec3f pwo = perturbed.to_local(si.to_world(wo));
        if (!(wo.z * pwo.z > 0.f)) return Color3(0.f);
        return nested_->eval(ctx, perturbed, pwo);
    }
    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const SurfaceInteraction perturbed = perturb(si);
        const Vec3f pwo = perturbed.to_local(si.to_world(wo));
        if (!(wo.z * pwo.z > 0.f)) return 0.f;
        return nested_->pdf(ctx, perturbed, pwo);
    }
    std::string to_string() const override { return "NormalMap[]"; }

  private:
    // The interaction with the normal-mapped shading frame and wi expressed in it.
    SurfaceInteraction perturb(const SurfaceInteraction& si) const {
        const Color3 c = normals_->eval(si);
        const Vec3f n_local(2.f * c.r - 1.f, 2.f * c.g - 1.f, 2.f * c.b - 1.f);
        SurfaceInteraction out(si);
        Frame f;
        f.n = normalize(si.to_world(n_local));
        f.s = normalize(si.dp_du - f.n * dot(f.n, si.dp_du));
        f.t = cross(f.n, f.s);
        out.sh_frame = f;
        out.wi = f.to_local(si.to_world(si.wi));
        return out;
    }

    std::shared_ptr<Texture> normals_;
    std::shared_ptr<BSDF> nested_;
};

}  // namespace

ObjectPtr make_normalmap_bsdf(const Properties& props) {
    return std::make_shared<NormalMapBSDF>(props);
}

}  // namespace volguide
