// `mask` (Mitsuba 3): an opacity mask around a nested BSDF. With probability opacity (`opacity`,
// texture or value in [0, 1], default 0.5, clipped as Mitsuba) the nested BSDF scatters; otherwise
// the ray passes straight through as through a `null` surface (a Null lobe with weight 1). eval and
// pdf are the nested BSDF's times the opacity; eval_null_transmission is 1 - opacity.
#include <algorithm>

#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"

namespace volguide {

namespace {

class MaskBSDF final : public BSDF {
  public:
    explicit MaskBSDF(const Properties& props) : opacity_(texture_param(props, "opacity", Color3(0.5f))) {
        auto children = props.children("bsdf");
        if (children.size() != 1) props.fail_here("mask: exactly one nested BSDF is required, got {}", children.size());
        nested_ = std::dynamic_pointer_cast<BSDF>(std::get<ObjectPtr>(children[0]->value));
        if (!nested_) props.fail_at(children[0]->name, "mask: nested object is not a BSDF");
        flags_ = nested_->flags() | bsdf_flags::Null;
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si, float sample1,
                                         Point2f sample2) const override {
        const float opacity = eval_opacity(si);
        if (sample1 >= opacity) {
            BSDFSample bs;
            bs.wo = -si.wi;
            bs.pdf = 1.f - opacity;
            bs.sampled_flags = bsdf_flags::Null;
            return {bs, Color3(1.f)};
        }
        // The same uniform, rescaled to [0, 1) for the nested BSDF's lobe choice.
        auto [bs, weight] = nested_->sample(ctx, si, std::min(sample1 / opacity, OneMinusEpsilon), sample2);
        bs.pdf *= opacity;
        return {bs, weight};
    }
    Color3 eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const override {
        return nested_->eval(ctx, si, wo) * eval_opacity(si);
    }
    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const override {
        return nested_->pdf(ctx, si, wo) * eval_opacity(si);
    }
    Color3 eval_null_transmission(const SurfaceInteraction& si) const override {
        return Color3(1.f - eval_opacity(si));
    }
    std::string to_string() const override { return "Mask[]"; }

  private:
    float eval_opacity(const SurfaceInteraction& si) const { return std::clamp(opacity_->eval_1(si), 0.f, 1.f); }

    std::shared_ptr<Texture> opacity_;
    std::shared_ptr<BSDF> nested_;
};

}  // namespace

ObjectPtr make_mask_bsdf(const Properties& props) {
    return std::make_shared<MaskBSDF>(props);
}

}  // namespace volguide
