// `roughplastic`: rough dielectric coating (Beckmann/GGX) over a diffuse base, Mitsuba's model.
// The diffuse lobe is attenuated by the rough interface's directional transmittance, which is
// tabulated over cos(theta) at construction by integrating the microfacet model numerically
// (64 entries, as Mitsuba); internal reflections use the hemispherically averaged internal
// reflectance of the rough interface.

#include <array>
#include <map>
#include <mutex>
#include <tuple>

#include "volguide/core/parallel.h"
#include "volguide/core/warp.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/bsdfs/bsdf_util.h"
#include "volguide/render/bsdfs/fresnel.h"
#include "volguide/render/bsdfs/ior.h"
#include "volguide/render/bsdfs/microfacet.h"

namespace volguide {

namespace {

constexpr int kTransmittanceRes = 64;

class RoughPlastic final : public BSDF {
  public:
    explicit RoughPlastic(const Properties& props) {
        const float int_ior = lookup_ior(props, "int_ior", "polypropylene");
        const float ext_ior = lookup_ior(props, "ext_ior", "air");
        if (int_ior == ext_ior) props.fail_here("roughplastic: the interior and exterior IOR must differ");
        eta_ = int_ior / ext_ior;
        diffuse_reflectance_ = nonnegative_texture(props, "diffuse_reflectance", Color3(0.5f));
        specular_reflectance_ = optional_texture(props, "specular_reflectance");
        nonlinear_ = props.get_bool("nonlinear", false);

        MicrofacetParams mp = MicrofacetParams::parse(props);
        if (mp.anisotropic) props.fail_at("alpha_u", "roughplastic does not support anisotropic roughness");
        if (!mp.alpha_u->is_constant())
            props.fail_at("alpha", "roughplastic: 'alpha' must be a number, not a texture");
        type_ = mp.type;
        sample_visible_ = mp.sample_visible;
        alpha_ = mp.alpha_u->mean().average();

        inv_eta_2_ = 1.f / (eta_ * eta_);
        const float d_mean = scalar_mean(diffuse_reflectance_), s_mean = scalar_mean(specular_reflectance_);
        specular_sampling_weight_ = s_mean / (d_mean + s_mean);
        precompute();
        flags_ = bsdf_flags::GlossyReflection | bsdf_flags::DiffuseReflection;
    }

    std::pair<BSDFSample, Color3> sample(const BSDFContext& ctx, const SurfaceInteraction& si, float sample1,
                                         Point2f sample2) const override {
        const float cos_theta_i = si.wi.z;
        if (cos_theta_i <= 0.f) return {BSDFSample{}, Color3(0.f)};
        const float prob_specular = specular_probability(cos_theta_i);
        BSDFSample bs;
        bs.eta = 1.f;
        if (sample1 < prob_specular) {
            const Vec3f m = distribution().sample(si.wi, sample2).first;
            bs.wo = reflect_about(si.wi, m);
            bs.sampled_flags = bsdf_flags::GlossyReflection;
        } else {
            bs.wo = warp::square_to_cosine_hemisphere(sample2);
            bs.sampled_flags = bsdf_flags::DiffuseReflection;
        }
        bs.pdf = pdf(ctx, si, bs.wo);
        if (!(bs.pdf > 0.f)) return {BSDFSample{}, Color3(0.f)};
        return {bs, eval(ctx, si, bs.wo) / bs.pdf};
    }

    Color3 eval(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const float cos_theta_i = si.wi.z, cos_theta_o = wo.z;
        if (!(cos_theta_i > 0.f && cos_theta_o > 0.f)) return Color3(0.f);
        const MicrofacetDistribution distr = distribution();
        const Vec3f h = normalize(wo + si.wi);
        const float D = distr.eval(h);
        const float F = fresnel_dielectric(dot(si.wi, h), eta_).F;
        const float G = distr.G(si.wi, wo, h);
        Color3 value = eval_or_one(specular_reflectance_, si) * (F * D * G / (4.f * cos_theta_i));

        const float t_i = transmittance(cos_theta_i), t_o = transmittance(cos_theta_o);
        const Color3 d = diffuse_reflectance_->eval(si);
        const Color3 denom =
            nonlinear_ ? Color3(1.f) - d * internal_reflectance_ : Color3(1.f - internal_reflectance_);
        value += (d / denom) * (InvPi * inv_eta_2_ * cos_theta_o * t_i * t_o);
        return value;
    }

    float pdf(const BSDFContext&, const SurfaceInteraction& si, const Vec3f& wo) const override {
        const float cos_theta_i = si.wi.z, cos_theta_o = wo.z;
        if (!(cos_theta_i > 0.f && cos_theta_o > 0.f)) return 0.f;
        const float prob_specular = specular_probability(cos_theta_i);
        const MicrofacetDistribution distr = distribution();
        const Vec3f h = normalize(wo + si.wi);
        float result = sample_visible_ ? distr.eval(h) * distr.smith_g1(si.wi, h) / (4.f * cos_theta_i)
                                       : distr.pdf(si.wi, h) / (4.f * dot(wo, h));
        result *= prob_specular;
        result += (1.f - prob_specular) * warp::square_to_cosine_hemisphere_pdf(wo);
        return result;
    }

    std::string to_string() const override { return "RoughPlastic[]"; }

  private:
    MicrofacetDistribution distribution() const {
        return MicrofacetDistribution(type_, alpha_, alpha_, sample_visible_);
    }

    // Linear interpolation in the table over cos(theta) in [0, 1].
    float transmittance(float cos_theta) const {
        const float x = cos_theta * float(kTransmittanceRes - 1);
        const int index = std::min(int(x), kTransmittanceRes - 2);
        return lerp(x - float(index), external_transmittance_[index], external_transmittance_[index + 1]);
    }

    float specular_probability(float cos_theta_i) const {
        const float t_i = transmittance(cos_theta_i);
        const float ps = (1.f - t_i) * specular_sampling_weight_,
                    pd = t_i * (1.f - specular_sampling_weight_);
        return ps / (ps + pd);
    }

    struct Tables {
        std::array<float, kTransmittanceRes> external_transmittance{};
        float internal_reflectance = 0.f;
    };

    // The integration takes a few hundred milliseconds for Beckmann; identical (type, alpha, eta)
    // share one result, and the 64 entries are computed in parallel.
    void precompute() {
        static std::mutex mutex;
        static std::map<std::tuple<int, float, float>, std::shared_ptr<const Tables>> cache;
        const auto key = std::make_tuple(int(type_), alpha_, eta_);
        std::shared_ptr<const Tables> tables;
        {
            std::lock_guard<std::mutex> lock(mutex);
            if (auto it = cache.find(key); it != cache.end()) tables = it->second;
        }
        if (!tables) {
            tables = compute_tables(type_, alpha_, eta_);
            std::lock_guard<std::mutex> lock(mutex);
            cache.emplace(key, tables);
        }
        external_transmittance_ = tables->external_transmittance;
        internal_reflectance_ = tables->internal_reflectance;
    }

    static std::shared_ptr<const Tables> compute_tables(MicrofacetType type, float alpha, float eta) {
        // Mitsuba integrates with visible-normal sampling regardless of `sample_visible`.
        const MicrofacetDistribution distr(type, alpha, alpha, true);
        auto tables = std::make_shared<Tables>();
        std::array<double, kTransmittanceRes> internal{};
        parallel_for(0, kTransmittanceRes, [&](int i) {
            const float mu = std::max(1e-6f, float(i) / float(kTransmittanceRes - 1));
            const Vec3f wi(std::sqrt(1.f - mu * mu), 0.f, mu);
            tables->external_transmittance[i] = rough_transmittance(distr, wi, eta);
            internal[i] = double(rough_reflectance(distr, wi, 1.f / eta)) * mu;
        });
        // Cosine-weighted hemispherical average: Mitsuba's mean over the uniform mu grid, times 2.
        double sum = 0.0;
        for (double v : internal) sum += v;
        tables->internal_reflectance = float(sum / kTransmittanceRes * 2.0);
        return tables;
    }

    float eta_, inv_eta_2_, alpha_, specular_sampling_weight_, internal_reflectance_ = 0.f;
    MicrofacetType type_;
    bool sample_visible_, nonlinear_;
    std::array<float, kTransmittanceRes> external_transmittance_{};
    std::shared_ptr<Texture> diffuse_reflectance_, specular_reflectance_;
};

}  // namespace

ObjectPtr make_rough_plastic_bsdf(const Properties& props) {
    return std::make_shared<RoughPlastic>(props);
}

}  // namespace volguide
