// `principled`: Mitsuba 3's principled BSDF (Burley's Disney BSDF with a specular transmission
// lobe): diffuse + retro-reflection (+ fake subsurface), sheen, a GGX specular lobe whose Fresnel
// blends dielectric, metallic and tinted responses, GGX transmission into the object, and a GTR1
// clearcoat. Same parameters, defaults, lobes and sampling weights as Mitsuba; docs/theory.md §18.1.
#include "volguide/core/math.h"
#include "volguide/core/warp.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/fresnel.h"
#include "volguide/render/bsdfs/principled_lobes.h"

namespace volguide::principled {

namespace {

// The textured values of one surface point and the two major lobes' weights.
struct PrincipledPoint {
    CommonValues v;
    float metallic = 0.f, clearcoat = 0.f;
    float brdf = 0.f;  // (1 - metallic)(1 - spec_trans): diffuse, retro-reflection, sheen
    float bsdf = 0.f;  // (1 - metallic) spec_trans: specular transmission
};

// Probabilities of the four sampling strategies, normalised (§18.1): front side diffuse, clearcoat
// and the main specular lobe split by the dielectric Fresnel F of the microfacet into reflection
// and transmission; back side only the specular lobe, split by F.
struct PrincipledLobeProbs {
    float diffuse = 0.f, clearcoat = 0.f, spec_trans = 0.f, spec_reflect = 0.f;
};

// The two configurations wo can be in, relative to wi, with the generalised half vector.
struct PrincipledGeometry {
    bool front = false, reflect = false, refract = false;
    float eta_path = 1.f;  // relative IOR along the light's path
    Vec3f wh;               // half vector, oriented to +z
    float F = 0.f;          // dielectric Fresnel at wh
};

class Principled final : public BSDF {
  public:
    explicit Principled(const Properties& props) {
        c_ = CommonParams::parse(props);
        has_metallic_ = has_flag(props, "metallic");
        has_clearcoat_ = has_flag(props, "clearcoat");
        metallic_ = texture_param(props, "metallic", Color3(0.f));
        clearcoat_ = texture_param(props, "clearcoat", Color3(0.f));
        clearcoat_gloss_ = texture_param(props, "clearcoat_gloss", Color3(0.f));
        spec_srate_ = sampling_rate(props, "main_specular_sampling_rate");
        clearcoat_srate_ = sampling_rate(props, "clearcoat_sampling_rate");
        diff_refl_srate_ = sampling_rate(props, "diffuse_reflectance_sampling_rate");
        eta_ = parse_eta(props);
        flags_ = bsdf_flags::DiffuseReflection | bsdf_flags::GlossyReflection;
        if (c_.has_spec_trans) flags_ |= bsdf_flags::GlossyTransmission;
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si, float sample1,
                                         Point2f sample2) const override {
        const float cos_theta_i = si.wi.z;
        if (cos_theta_i == 0.f) return {BSDFSample{}, Color3(0.f)};
        const PrincipledPoint pt = at(si);
        const bool front = cos_theta_i > 0.f;
        // Inside, only the transmission lobe's reflection and refraction exist.
        if (!front && !(pt.bsdf > 0.f)) return {BSDFSample{}, Color3(0.f)};
        const MicrofacetDistribution distr = main_distribution(pt.v.anisotropic, pt.v.roughness, c_.has_anisotropic);
        const Vec3f m = distr.sample(flip_to_sign(si.wi, cos_theta_i), sample2).first;
        const FresnelResult fr = fresnel_dielectric(dot(si.wi, m), eta_);
        const PrincipledLobeProbs pr = probs(pt, front, fr.F);

        BSDFSample bs;
        bool valid;
        if (sample1 < pr.diffuse) {
            bs.wo = warp::square_to_cosine_hemisphere(sample2);
            bs.sampled_flags = bsdf_flags::DiffuseReflection;
            valid = cos_theta_i * bs.wo.z > 0.f;
        } else if (sample1 < pr.diffuse + pr.clearcoat) {
            const Vec3f m_cc = Gtr1(clearcoat_alpha(si)).sample(sample2);
            bs.wo = reflect_about(si.wi, m_cc);
            bs.sampled_flags = bsdf_flags::GlossyReflection;
            valid = cos_theta_i * bs.wo.z > 0.f && microfacet_compatible(m_cc, si.wi, bs.wo, cos_theta_i, true);
        } else if (sample1 < pr.diffuse + pr.clearcoat + pr.spec_trans) {
            bs.wo = refract_about(si.wi, m, fr.cos_theta_t, fr.eta_ti);
            bs.sampled_flags = bsdf_flags::GlossyTransmission;
            bs.eta = fr.eta_it;
            valid = cos_theta_i * bs.wo.z < 0.f && microfacet_compatible(m, si.wi, bs.wo, cos_theta_i, false);
        } else {
            bs.wo = reflect_about(si.wi, m);
            bs.sampled_flags = bsdf_flags::GlossyReflection;
            valid = cos_theta_i * bs.wo.z > 0.f && microfacet_compatible(m, si.wi, bs.wo, cos_theta_i, true);
        }
        if (!valid) return {BSDFSample{}, Color3(0.f)};
        bs.pdf = pdf(ctx, si, bs.wo);
        if (!(bs.pdf > 0.f)) return {BSDFSample{}, Color3(0.f)};
        return {bs, eval(ctx, si, bs.wo) / bs.pdf};
    }

    Color3 eval(const BSDFContext& ctx, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const float cos_theta_i = si.wi.z, cos_theta_o = wo.z;
        if (cos_theta_i == 0.f) return Color3(0.f);
        const PrincipledPoint pt = at(si);
        const PrincipledGeometry g = geometry(si.wi, wo);
        if (!g.reflect && !g.refract) return Color3(0.f);
        const MicrofacetDistribution distr = main_distribution(pt.v.anisotropic, pt.v.roughness, c_.has_anisotropic);
        const bool compat_reflect = g.reflect && microfacet_compatible(g.wh, si.wi, wo, cos_theta_i, true);
        Color3 value(0.f);
        if (compat_reflect && g.F > 0.f) value += specular_reflection(pt, g, distr, si.wi, wo);
        if (c_.has_spec_trans && pt.bsdf > 0.f && g.refract && g.F < 1.f &&
            microfacet_compatible(g.wh, si.wi, wo, cos_theta_i, false))
            value += specular_transmission(ctx, pt, g, distr, si.wi, wo);
        if (has_clearcoat_ && pt.clearcoat > 0.f && compat_reflect && g.front)
            value += Color3(clearcoat_value(si, pt, g, wo));
        if (pt.brdf > 0.f && g.reflect && g.front) {
            const float cos_theta_d = dot(g.wh, wo);
            value += diffuse_term(pt.v, c_.has_flatness, cos_theta_i, cos_theta_o, cos_theta_d) * pt.brdf;
            if (c_.has_sheen && pt.v.sheen > 0.f && 1.f - pt.metallic > 0.f)
                value += sheen_term(pt.v, c_.has_sheen_tint, cos_theta_o, cos_theta_d) * (1.f - pt.metallic);
        }
        return value;
    }

    float pdf(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const float cos_theta_i = si.wi.z;
        if (cos_theta_i == 0.f) return 0.f;
        const PrincipledPoint pt = at(si);
        const PrincipledGeometry g = geometry(si.wi, wo);
        // sample() never leaves the inside without a transmission lobe (Mitsuba's pdf() is non-zero
        // there, where its eval() is zero).
        if ((!g.reflect && !g.refract) || (!g.front && !(pt.bsdf > 0.f))) return 0.f;
        const PrincipledLobeProbs pr = probs(pt, g.front, g.F);
        const MicrofacetDistribution distr = main_distribution(pt.v.anisotropic, pt.v.roughness, c_.has_anisotropic);
        const float dot_wi_h = dot(si.wi, g.wh), dot_wo_h = dot(wo, g.wh);
        const float dwh_dwo = g.reflect ? std::abs(1.f / (4.f * dot_wo_h))
                                        : std::abs(sqr(g.eta_path) * dot_wo_h / sqr(dot_wi_h + g.eta_path * dot_wo_h));
        const float pdf_m = distr.pdf(flip_to_sign(si.wi, cos_theta_i), g.wh);
        float result = 0.f;
        if (g.reflect) {
            if (microfacet_compatible(g.wh, si.wi, wo, cos_theta_i, true)) {
                result += pr.spec_reflect * pdf_m * dwh_dwo;
                if (pr.clearcoat > 0.f) result += pr.clearcoat * Gtr1(clearcoat_alpha(si)).pdf(g.wh) * dwh_dwo;
            }
            result += pr.diffuse * warp::square_to_cosine_hemisphere_pdf(wo);
        } else if (microfacet_compatible(g.wh, si.wi, wo, cos_theta_i, false)) {
            result += pr.spec_trans * pdf_m * dwh_dwo;
        }
        return result;
    }

    std::string to_string() const override { return "Principled[]"; }

  private:
    // `eta`, or `specular` mapped to it (eta = 2 / (1 - sqrt(0.08 specular)) - 1), never both;
    // a transmission lobe nudges an index-matched interface away from eta = 1.
    float parse_eta(const Properties& props) const {
        if (props.has("eta") && props.has("specular"))
            props.fail_at("specular", "principled: give either 'eta' or 'specular', not both");
        if (props.has("eta")) {
            float eta = props.get_float("eta");
            if (!(eta > 0.f && std::isfinite(eta))) props.fail_at("eta", "principled: 'eta' must be positive");
            if (c_.has_spec_trans && eta == 1.f) eta = 1.001f;
            return eta;
        }
        float specular = props.get_float("specular", 0.5f);
        if (!(specular >= 0.f && specular < 12.5f))
            props.fail_at("specular", "principled: 'specular' must lie in [0, 12.5) (got {})", specular);
        if (c_.has_spec_trans && specular == 0.f) specular = 1e-3f;
        return 2.f / (1.f - std::sqrt(0.08f * specular)) - 1.f;
    }

    PrincipledPoint at(const SurfaceInteraction& si) const {
        PrincipledPoint pt;
        pt.v = CommonValues::at(c_, si);
        if (has_metallic_) pt.metallic = metallic_->eval_1(si);
        if (has_clearcoat_) pt.clearcoat = clearcoat_->eval_1(si);
        pt.brdf = (1.f - pt.metallic) * (1.f - pt.v.spec_trans);
        pt.bsdf = (1.f - pt.metallic) * pt.v.spec_trans;
        return pt;
    }

    // Clearcoat roughness: 0.1 (gloss 0) to 0.001 (gloss 1).
    float clearcoat_alpha(const SurfaceInteraction& si) const {
        const float gloss = clearcoat_gloss_->eval_1(si);
        return 0.1f + (0.001f - 0.1f) * gloss;
    }

    PrincipledLobeProbs probs(const PrincipledPoint& pt, bool front, float F) const {
        PrincipledLobeProbs pr;
        if (front) {
            pr.spec_reflect = spec_srate_ * (1.f - pt.bsdf * (1.f - F));
            if (c_.has_spec_trans) pr.spec_trans = spec_srate_ * pt.bsdf * (1.f - F);
            if (has_clearcoat_) pr.clearcoat = std::max(0.f, 0.25f * pt.clearcoat * clearcoat_srate_);
            pr.diffuse = std::max(0.f, pt.brdf * diff_refl_srate_);
        } else {
            pr.spec_reflect = F;
            if (c_.has_spec_trans) pr.spec_trans = 1.f - F;
        }
        const float total = pr.diffuse + pr.clearcoat + pr.spec_trans + pr.spec_reflect;
        if (!(total > 0.f)) return PrincipledLobeProbs{};
        pr.diffuse /= total;
        pr.clearcoat /= total;
        pr.spec_trans /= total;
        pr.spec_reflect /= total;
        return pr;
    }

    PrincipledGeometry geometry(const Vec3f& wi, const Vec3f& wo) const {
        PrincipledGeometry g;
        g.front = wi.z > 0.f;
        g.reflect = wi.z * wo.z > 0.f;
        g.refract = wi.z * wo.z < 0.f;
        g.eta_path = g.front ? eta_ : 1.f / eta_;
        const Vec3f h = wi + wo * (g.reflect ? 1.f : g.eta_path);
        const float len = norm(h);
        if (!(len > 0.f)) {
            g.reflect = g.refract = false;
            return g;
        }
        g.wh = flip_to_sign(h / len, h.z);
        g.F = fresnel_dielectric(dot(wi, g.wh), eta_).F;
        return g;
    }

    // Specular reflection: F_principled D G / (4 |cos_theta_i|); on the front side F blends the
    // dielectric, metallic and tinted responses, inside it is the transmission lobe's dielectric F.
    Color3 specular_reflection(const PrincipledPoint& pt, const PrincipledGeometry& g,
                               const MicrofacetDistribution& distr, const Vec3f& wi, const Vec3f& wo) const {
        const float cos_h = dot(wi, g.wh);
        Color3 F(pt.bsdf * g.F);
        if (g.front) {
            Color3 F_schlick(0.f);
            if (has_metallic_) F_schlick += pt.metallic * schlick_fresnel(pt.v.base_color, cos_h, eta_);
            if (c_.has_spec_tint) {
                const float eta_it = cos_h >= 0.f ? eta_ : 1.f / eta_;
                const Color3 F0 = tint_color(pt.v.base_color) * schlick_r0(eta_it);
                F_schlick += (1.f - pt.metallic) * pt.v.spec_tint * schlick_fresnel(F0, cos_h, eta_);
            }
            F = Color3((1.f - pt.metallic) * (1.f - pt.v.spec_tint) * g.F) + F_schlick;
        }
        return F * (distr.eval(g.wh) * distr.G(wi, wo, g.wh) / (4.f * std::abs(wi.z)));
    }

    // Walter et al.'s rough transmission, tinted by sqrt(base_color) and weighted by bsdf.
    Color3 specular_transmission(const BSDFContext& ctx, const PrincipledPoint& pt, const PrincipledGeometry& g,
                                 const MicrofacetDistribution& distr, const Vec3f& wi, const Vec3f& wo) const {
        const float scale = ctx.mode == TransportMode::Radiance ? 1.f / sqr(g.eta_path) : 1.f;
        const float dot_wi_h = dot(wi, g.wh), dot_wo_h = dot(wo, g.wh);
        const float value = std::abs(scale * (1.f - g.F) * distr.eval(g.wh) * distr.G(wi, wo, g.wh) *
                                     sqr(g.eta_path) * dot_wi_h * dot_wo_h /
                                     (wi.z * sqr(dot_wi_h + g.eta_path * dot_wo_h)));
        return sqrt(pt.v.base_color) * (pt.bsdf * value);
    }

    // Mitsuba's clearcoat: 0.25 clearcoat F_schlick(0.04) D_GTR1 G_GGX(0.25) |cos_theta_o| (as
    // written there: no 1/(4 cos_theta_i cos_theta_o); §18.1).
    float clearcoat_value(const SurfaceInteraction& si, const PrincipledPoint& pt, const PrincipledGeometry& g,
                          const Vec3f& wo) const {
        const float Fcc = schlick_fresnel(0.04f, dot(si.wi, g.wh), eta_);
        const float Dcc = Gtr1(clearcoat_alpha(si)).eval(g.wh);
        const float Gcc = smith_ggx1(si.wi, g.wh, 0.25f) * smith_ggx1(wo, g.wh, 0.25f);
        return 0.25f * pt.clearcoat * Fcc * Dcc * Gcc * std::abs(wo.z);
    }

    CommonParams c_;
    std::shared_ptr<Texture> metallic_, clearcoat_, clearcoat_gloss_;
    bool has_metallic_ = false, has_clearcoat_ = false;
    float eta_ = 1.5f;
    float spec_srate_ = 1.f, clearcoat_srate_ = 1.f, diff_refl_srate_ = 1.f;
};

}  // namespace

}  // namespace volguide::principled

namespace volguide {

ObjectPtr make_principled_bsdf(const Properties& props) {
    return std::make_shared<principled::Principled>(props);
}

}  // namespace volguide
