// `twosided`: makes one-sided reflectance models two-sided. With one nested BSDF both sides use
// it (wi and wo are mirrored to the front side); with two, the second one is used for the back.
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"

namespace volguide {

namespace {

class TwoSided final : public BSDF {
  public:
    explicit TwoSided(const Properties& props) {
        auto children = props.children("bsdf");
        if (children.empty()) props.fail_here("twosided: a nested BSDF is required");
        if (children.size() > 2)
            props.fail_at(children[2]->name, "twosided: at most two nested BSDFs can be specified");
        for (size_t i = 0; i < children.size(); ++i) {
            auto bsdf = std::dynamic_pointer_cast<BSDF>(std::get<ObjectPtr>(children[i]->value));
            if (!bsdf) props.fail_at(children[i]->name, "twosided: nested object is not a BSDF");
            if (bsdf->has(bsdf_flags::Transmission))
                props.fail_at(children[i]->name,
                              "twosided: only materials without transmission can be nested");
            brdf_[i] = std::move(bsdf);
        }
        if (!brdf_[1]) brdf_[1] = brdf_[0];
        flags_ = brdf_[0]->flags() | brdf_[1]->flags();
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si_, float sample1,
                                         Point2f sample2) const override {
        SurfaceInteraction si(si_);
        if (brdf_[0] == brdf_[1]) {
            si.wi.z = std::abs(si.wi.z);
            auto result = brdf_[0]->sample(ctx, si, sample1, sample2);
            if (si_.wi.z < 0.f) result.first.wo.z = -result.first.wo.z;
            return result;
        }
        if (si.wi.z > 0.f) return brdf_[0]->sample(ctx, si, sample1, sample2);
        if (si.wi.z < 0.f) {
            si.wi.z = -si.wi.z;
            auto result = brdf_[1]->sample(ctx, si, sample1, sample2);
            result.first.wo.z = -result.first.wo.z;
            return result;
        }
        return {BSDFSample{}, Color3(0.f)};
    }

    Color3 eval(const BSDFContext& ctx, const SurfaceInteraction& si_, const Vec3f& wo_) const override {
        SurfaceInteraction si(si_);
        Vec3f wo(wo_);
        const BSDF* b = front_side(si, wo);
        return b ? b->eval(ctx, si, wo) : Color3(0.f);
    }

    float pdf(const BSDFContext& ctx, const SurfaceInteraction& si_, const Vec3f& wo_) const override {
        SurfaceInteraction si(si_);
        Vec3f wo(wo_);
        const BSDF* b = front_side(si, wo);
        return b ? b->pdf(ctx, si, wo) : 0.f;
    }

    std::string to_string() const override { return "TwoSided[]"; }

  private:
    // Mirrors (wi, wo) so that wi is on the front side; returns the BSDF to use (null if grazing
    // with two different BSDFs).
    const BSDF* front_side(SurfaceInteraction& si, Vec3f& wo) const {
        if (brdf_[0] == brdf_[1]) {
            if (si.wi.z < 0.f) wo.z = -wo.z;
            si.wi.z = std::abs(si.wi.z);
            return brdf_[0].get();
        }
        if (si.wi.z > 0.f) return brdf_[0].get();
        if (si.wi.z < 0.f) {
            si.wi.z = -si.wi.z;
            wo.z = -wo.z;
            return brdf_[1].get();
        }
        return nullptr;
    }

    std::shared_ptr<BSDF> brdf_[2];
};

}  // namespace

ObjectPtr make_twosided_bsdf(const Properties& props) {
    return std::make_shared<TwoSided>(props);
}

}  // namespace volguide
