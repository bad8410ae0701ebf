// `blendbsdf` (Mitsuba 3): the linear blend (1 - w) f_0 + w f_1 of two nested BSDFs, with w =
// `weight` (a texture or value, clipped to [0, 1]). sample() picks BSDF 1 with probability w and
// BSDF 0 otherwise. For a smooth lobe the returned pdf is the blend's, (1 - w) p_0 + w p_1, and the
// weight eval/pdf, so sample/pdf/eval agree (Mitsuba returns the picked BSDF's own pdf and weight,
// which has the same expectation); for a delta lobe the pick's probability times the nested
// discrete pdf, with the nested weight (the other BSDF adds nothing along a delta direction).
#include <algorithm>

#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"

namespace volguide {

namespace {

class BlendBSDF final : public BSDF {
  public:
    explicit BlendBSDF(const Properties& props) : weight_(texture_param(props, "weight")) {
        auto children = props.children("bsdf");
        if (children.size() != 2)
            props.fail_here("blendbsdf: exactly two nested BSDFs are required, got {}", children.size());
        for (int i = 0; i < 2; ++i) {
            nested_[i] = std::dynamic_pointer_cast<BSDF>(std::get<ObjectPtr>(children[size_t(i)]->value));
            if (!nested_[i]) props.fail_at(children[size_t(i)]->name, "blendbsdf: nested object is not a BSDF");
        }
        flags_ = nested_[0]->flags() | nested_[1]->flags();
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si, float sample1,
                                         Point2f sample2) const override {
        const float w = eval_weight(si);
        const int pick = sample1 < w ? 1 : 0;
        const float p_pick = pick == 1 ? w : 1.f - w;
        // The same uniform, rescaled to [0, 1) for the nested BSDF's own lobe choice.
        const float rescaled = pick == 1 ? sample1 / w : (sample1 - w) / (1.f - w);
        auto [bs, weight] = nested_[pick]->sample(ctx, si, std::min(rescaled, OneMinusEpsilon), sample2);
        if (bs.pdf <= 0.f) return {bs, Color3(0.f)};
        if (bs.sampled_flags & bsdf_flags::Delta) {
            bs.pdf *= p_pick;
            return {bs, weight};
        }
        bs.pdf = pdf_blend(ctx, si, bs.wo, w);
        if (!(bs.pdf > 0.f)) return {bs, Color3(0.f)};
        return {bs, eval_blend(ctx, si, bs.wo, w) / bs.pdf};
    }
    Color3 eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const override {
        return eval_blend(ctx, si, wo, eval_weight(si));
    }
    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const override {
        return pdf_blend(ctx, si, wo, eval_weight(si));
    }
    Color3 eval_null_transmission(const SurfaceInteraction& si) const override {
        const float w = eval_weight(si);
        return nested_[0]->eval_null_transmission(si) * (1.f - w) + nested_[1]->eval_null_transmission(si) * w;
    }
    std::string to_string() const override { return "BlendBSDF[]"; }

  private:
    float eval_weight(const SurfaceInteraction& si) const { return std::clamp(weight_->eval_1(si), 0.f, 1.f); }
    Color3 eval_blend(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo, float w) const {
        Color3 f(0.f);
        if (w < 1.f) f += nested_[0]->eval(ctx, si, wo) * (1.f - w);
        if (w > 0.f) f += nested_[1]->eval(ctx, si, wo) * w;
        return f;
    }
    float pdf_blend(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo, float w) const {
        float p = 0.f;
        if (w < 1.f) p += nested_[0]->pdf(ctx, si, wo) * (1.f - w);
        if (w > 0.f) p += nested_[1]->pdf(ctx, si, wo) * w;
        return p;
    }

    std::shared_ptr<Texture> weight_;
    std::shared_ptr<BSDF> nested_[2];
};

}  // namespace

ObjectPtr make_blend_bsdf(const Properties& props) {
    return std::make_shared<BlendBSDF>(props);
}

}  // namespace volguide
