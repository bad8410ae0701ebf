// `principledthin`: Mitsuba 3's thin principled BSDF (Burley 2015's thin-surface model): a two-sided
// sheet with diffuse + retro-reflection (+ fake subsurface) and sheen, Lambertian diffuse
// transmission (`diff_trans`, 0..2), and a GGX specular reflection and an unrefracted GGX specular
// transmission of roughness scaled by the sheet's IOR. Same parameters, defaults, lobes and sampling
// weights as Mitsuba; docs/theory.md §18.2.
#include "volguide/core/math.h"
#include "volguide/core/warp.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/fresnel.h"
#include "volguide/render/bsdfs/principled_lobes.h"

namespace volguide::principled {

namespace {

struct ThinPoint {
    CommonValues v;
    float eta = 1.5f;
    float diff_trans = 0.f;  // diff_trans / 2, in 0..1
};

// Normalised probabilities of the four strategies (§18.2); they depend on the point only.
struct ThinLobeProbs {
    float spec_reflect = 0.f, spec_trans = 0.f, diff_reflect = 0.f, diff_trans = 0.f;
};

// wi and wo mirrored to wi's side being +z (the sheet is symmetric), and the half vector of wi and
// wo mirrored into the upper hemisphere.
struct ThinGeometry {
    Vec3f wi, wo;  // wo: wo_t, mirrored with wi
    Vec3f wh;
    bool reflect = false, refract = false;
};

class PrincipledThin final : public BSDF {
  public:
    explicit PrincipledThin(const Properties& props) {
        c_ = CommonParams::parse(props);
        has_diff_trans_ = has_flag(props, "diff_trans");
        diff_trans_ = texture_param(props, "diff_trans", Color3(0.f));
        eta_ = texture_param(props, "eta", Color3(1.5f));
        spec_refl_srate_ = sampling_rate(props, "specular_reflectance_sampling_rate");
        spec_trans_srate_ = sampling_rate(props, "specular_transmittance_sampling_rate");
        diff_trans_srate_ = sampling_rate(props, "diffuse_transmittance_sampling_rate");
        diff_refl_srate_ = sampling_rate(props, "diffuse_reflectance_sampling_rate");
        flags_ = bsdf_flags::DiffuseReflection | bsdf_flags::DiffuseTransmission | bsdf_flags::GlossyReflection;
        if (c_.has_spec_trans) flags_ |= bsdf_flags::GlossyTransmission;
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si, float sample1,
                                         Point2f sample2) const override {
        const float cos_theta_i = si.wi.z;
        if (cos_theta_i == 0.f) return {BSDFSample{}, Color3(0.f)};
        const ThinPoint pt = at(si);
        const ThinLobeProbs pr = probs(pt);
        const Vec3f wi = flip_to_sign(si.wi, cos_theta_i);
        BSDFSample bs;
        bool valid = true;
        if (sample1 < pr.spec_reflect) {
            const Vec3f m = reflect_distribution(pt).sample(wi, sample2).first;
            bs.wo = reflect_about(wi, m);
            bs.sampled_flags = bsdf_flags::GlossyReflection;
            valid = bs.wo.z > 0.f && microfacet_compatible(m, wi, bs.wo, wi.z, true);
        } else if (sample1 < pr.spec_reflect + pr.spec_trans) {
            // The sheet does not bend light: the reflected direction, mirrored to the other side.
            const Vec3f m = transmit_distribution(pt).sample(wi, sample2).first;
            bs.wo = reflect_about(wi, m);
            bs.wo.z = -bs.wo.z;
            bs.sampled_flags = bsdf_flags::GlossyTransmission;
            valid = bs.wo.z < 0.f && microfacet_compatible(m, wi, bs.wo, wi.z, false);
        } else if (sample1 < pr.spec_reflect + pr.spec_trans + pr.diff_reflect || !has_diff_trans_) {
            bs.wo = warp::square_to_cosine_hemisphere(sample2);
            bs.sampled_flags = bsdf_flags::DiffuseReflection;
        } else {
            bs.wo = -warp::square_to_cosine_hemisphere(sample2);
            bs.sampled_flags = bsdf_flags::DiffuseTransmission;
        }
        if (!valid) return {BSDFSample{}, Color3(0.f)};
        bs.wo = flip_to_sign(bs.wo, cos_theta_i);
        bs.eta = 1.f;
        bs.pdf = pdf(ctx, si, bs.wo);
        if (!(bs.pdf > 0.f)) return {BSDFSample{}, Color3(0.f)};
        return {bs, eval(ctx, si, bs.wo) / bs.pdf};
    }

    Color3 eval(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        if (si.wi.z == 0.f) return Color3(0.f);
        const ThinPoint pt = at(si);
        const ThinGeometry g = geometry(si.wi, wo);
        const float st = pt.v.spec_trans, dt = pt.diff_trans, cos_theta_i = g.wi.z, cos_theta_o = g.wo.z;
        Color3 value(0.f);
        if (c_.has_spec_trans && st > 0.f) value += specular(pt, g);
        if (g.reflect && st < 1.f && dt < 1.f) {
            const float cos_theta_d = dot(g.wh, g.wo), w = (1.f - st) * (1.f - dt);
            value += diffuse_term(pt.v, c_.has_flatness, cos_theta_i, cos_theta_o, cos_theta_d) * w;
            if (c_.has_sheen && pt.v.sheen > 0.f)
                value += sheen_term(pt.v, c_.has_sheen_tint, cos_theta_o, cos_theta_d) * w;
        }
        if (has_diff_trans_ && g.refract && st < 1.f && dt > 0.f)
            value += pt.v.base_color * ((1.f - st) * dt * InvPi * std::abs(cos_theta_o));
        return value;
    }

    float pdf(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        if (si.wi.z == 0.f) return 0.f;
        const ThinPoint pt = at(si);
        const ThinLobeProbs pr = probs(pt);
        const ThinGeometry g = geometry(si.wi, wo);
        float result = 0.f;
        if (c_.has_spec_trans && (g.reflect || g.refract)) {
            const Vec3f wo_r(g.wo.x, g.wo.y, std::abs(g.wo.z));
            const float dwh_dwo = std::abs(1.f / (4.f * dot(wo_r, g.wh)));
            if (g.reflect && microfacet_compatible(g.wh, g.wi, g.wo, g.wi.z, true))
                result += pr.spec_reflect * reflect_distribution(pt).pdf(g.wi, g.wh) * dwh_dwo;
            if (g.refract && microfacet_compatible(g.wh, g.wi, g.wo, g.wi.z, false))
                result += pr.spec_trans * transmit_distribution(pt).pdf(g.wi, g.wh) * dwh_dwo;
        }
        if (g.reflect) result += pr.diff_reflect * warp::square_to_cosine_hemisphere_pdf(g.wo);
        if (has_diff_trans_ && g.refract) result += pr.diff_trans * warp::square_to_cosine_hemisphere_pdf(-g.wo);
        return result;
    }

    std::string to_string() const override { return "PrincipledThin[]"; }

  private:
    ThinPoint at(const SurfaceInteraction& si) const {
        ThinPoint pt;
        pt.v = CommonValues::at(c_, si);
        pt.eta = eta_->eval_1(si);
        if (has_diff_trans_) pt.diff_trans = 0.5f * diff_trans_->eval_1(si);
        return pt;
    }

    // Out-of-range textured weights would make a probability negative; they are clamped to zero
    // (sampling only: eval() keeps Mitsuba's expression).
    ThinLobeProbs probs(const ThinPoint& pt) const {
        const float st = pt.v.spec_trans, dt = pt.diff_trans;
        ThinLobeProbs pr;
        if (c_.has_spec_trans) {
            pr.spec_reflect = std::max(0.f, 0.5f * st * spec_refl_srate_);
            pr.spec_trans = std::max(0.f, 0.5f * st * spec_trans_srate_);
        }
        pr.diff_reflect = std::max(0.f, diff_refl_srate_ * (1.f - st) * (1.f - dt));
        if (has_diff_trans_) pr.diff_trans = std::max(0.f, diff_trans_srate_ * (1.f - st) * dt);
        const float total = pr.spec_reflect + pr.spec_trans + pr.diff_reflect + pr.diff_trans;
        if (!(total > 0.f)) return ThinLobeProbs{};
        pr.spec_reflect /= total;
        pr.spec_trans /= total;
        pr.diff_reflect /= total;
        pr.diff_trans /= total;
        return pr;
    }

    MicrofacetDistribution reflect_distribution(const ThinPoint& pt) const {
        return main_distribution(pt.v.anisotropic, pt.v.roughness, c_.has_anisotropic);
    }
    // Transmission roughness scaled by the IOR (Burley 2015, figure 15).
    MicrofacetDistribution transmit_distribution(const ThinPoint& pt) const {
        return main_distribution(pt.v.anisotropic, (0.65f * pt.eta - 0.35f) * pt.v.roughness, c_.has_anisotropic);
    }

    static ThinGeometry geometry(const Vec3f& wi, const Vec3f& wo) {
        ThinGeometry g;
        g.wi = flip_to_sign(wi, wi.z);
        g.wo = flip_to_sign(wo, wi.z);
        g.reflect = g.wo.z > 0.f;
        g.refract = g.wo.z < 0.f;
        g.wh = normalize(g.wi + Vec3f(g.wo.x, g.wo.y, std::abs(g.wo.z)));
        return g;
    }

    // spec_trans-weighted GGX reflection (tinted Fresnel) and unrefracted transmission (base_color,
    // 1 - F), both D G / (4 cos_theta_i) of their distribution at the mirrored half vector.
    Color3 specular(const ThinPoint& pt, const ThinGeometry& g) const {
        const float F = fresnel_dielectric(dot(g.wi, g.wh), pt.eta).F, st = pt.v.spec_trans;
        const float norm = 1.f / (4.f * g.wi.z);
        if (g.reflect && microfacet_compatible(g.wh, g.wi, g.wo, g.wi.z, true)) {
            Color3 F_thin(F);
            if (c_.has_spec_tint) {
                const Color3 F0 = tint_color(pt.v.base_color) * schlick_r0(pt.eta);
                const Color3 F_schlick = schlick_fresnel(F0, dot(g.wi, g.wh), pt.eta);
                F_thin = Color3(F * (1.f - pt.v.spec_tint)) + F_schlick * pt.v.spec_tint;
            }
            const MicrofacetDistribution distr = reflect_distribution(pt);
            return F_thin * (st * distr.eval(g.wh) * distr.G(g.wi, g.wo, g.wh) * norm);
        }
        if (g.refract && microfacet_compatible(g.wh, g.wi, g.wo, g.wi.z, false)) {
            const MicrofacetDistribution distr = transmit_distribution(pt);
            return pt.v.base_color * (st * (1.f - F) * distr.eval(g.wh) * distr.G(g.wi, g.wo, g.wh) * norm);
        }
        return Color3(0.f);
    }

    CommonParams c_;
    std::shared_ptr<Texture> diff_trans_, eta_;
    bool has_diff_trans_ = false;
    float spec_refl_srate_ = 1.f, spec_trans_srate_ = 1.f, diff_trans_srate_ = 1.f, diff_refl_srate_ = 1.f;
};

}  // namespace

}  // namespace volguide::principled

namespace volguide {

ObjectPtr make_principled_thin_bsdf(const Properties& props) {
    return std::make_shared<principled::PrincipledThin>(props);
}

}  // namespace volguide
