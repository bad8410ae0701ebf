#include "volguide/render/bsdfs/principled_lobes.h"

#include <algorithm>
#include <cmath>

#include "volguide/core/math.h"

namespace volguide::principled {

float schlick_fresnel_weight(float cos_theta_i, float eta) {
    const bool outside = cos_theta_i >= 0.f;
    const float eta_it = outside ? eta : 1.f / eta, eta_ti = outside ? 1.f / eta : eta;
    if (eta_it > 1.f) return schlick_weight(std::abs(cos_theta_i));
    const float cos_theta_t = safe_sqrt(1.f - (1.f - cos_theta_i * cos_theta_i) * eta_ti * eta_ti);
    return schlick_weight(cos_theta_t);
}

MicrofacetDistribution main_distribution(float anisotropic, float roughness, bool has_anisotropic) {
    const float r2 = roughness * roughness;
    if (!has_anisotropic) {
        const float a = std::max(0.001f, r2);
        return MicrofacetDistribution(MicrofacetType::GGX, a, a);
    }
    const float aspect = std::sqrt(1.f - 0.9f * anisotropic);
    return MicrofacetDistribution(MicrofacetType::GGX, std::max(0.001f, r2 / aspect), std::max(0.001f, r2 * aspect));
}

bool microfacet_compatible(const Vec3f& m, const Vec3f& wi, const Vec3f& wo, float cos_theta_i, bool reflection) {
    const Vec3f m_i = flip_to_sign(m, cos_theta_i);
    if (!(dot(wi, m_i) > 0.f)) return false;
    return reflection ? dot(wo, m_i) > 0.f : dot(wo, m_i) < 0.f;
}

float Gtr1::eval(const Vec3f& m) const {
    const float cos_theta = m.z, alpha2 = alpha_ * alpha_;
    const float result = (alpha2 - 1.f) / (Pi * std::log(alpha2) * (1.f + (alpha2 - 1.f) * cos_theta * cos_theta));
    return result * cos_theta > 1e-20f ? result : 0.f;
}

Vec3f Gtr1::sample(Point2f u) const {
    const float phi = 2.f * Pi * u.x, alpha2 = alpha_ * alpha_;
    const float cos_theta2 = (1.f - std::pow(alpha2, 1.f - u.y)) / (1.f - alpha2);
    const float sin_theta = safe_sqrt(1.f - cos_theta2), cos_theta = safe_sqrt(cos_theta2);
    return {std::cos(phi) * sin_theta, std::sin(phi) * sin_theta, cos_theta};
}

float smith_ggx1(const Vec3f& v, const Vec3f& wh, float alpha) {
    if (dot(v, wh) * v.z <= 0.f) return 0.f;
    if (v.z == 1.f) return 1.f;
    const float cos2 = v.z * v.z, tan2 = (1.f - cos2) / cos2;
    return 2.f / (1.f + std::sqrt(1.f + alpha * alpha * tan2));
}

bool has_flag(const Properties& props, const std::string& name) {
    const Properties::Entry* e = props.find(name);
    if (!e) return false;
    if (e->category == "float" && std::holds_alternative<double>(e->value)) return std::get<double>(e->value) != 0.0;
    return true;
}

float sampling_rate(const Properties& props, const std::string& name) {
    const float rate = props.get_float(name, 1.f);
    if (!(rate >= 0.f && std::isfinite(rate))) props.fail_at(name, "'{}' must be finite and non-negative", name);
    return rate;
}

CommonParams CommonParams::parse(const Properties& props) {
    CommonParams p;
    auto weight = [&](const char* name, bool& has) {
        has = has_flag(props, name);
        return texture_param(props, name, Color3(0.f));
    };
    p.base_color = texture_param(props, "base_color", Color3(0.5f));
    p.roughness = texture_param(props, "roughness", Color3(0.5f));
    p.anisotropic = weight("anisotropic", p.has_anisotropic);
    p.spec_trans = weight("spec_trans", p.has_spec_trans);
    p.sheen = weight("sheen", p.has_sheen);
    p.sheen_tint = weight("sheen_tint", p.has_sheen_tint);
    p.flatness = weight("flatness", p.has_flatness);
    p.spec_tint = weight("spec_tint", p.has_spec_tint);
    return p;
}

CommonValues CommonValues::at(const CommonParams& p, const SurfaceInteraction& si) {
    CommonValues v;
    v.base_color = p.base_color->eval(si);
    v.roughness = p.roughness->eval_1(si);
    if (p.has_anisotropic) v.anisotropic = p.anisotropic->eval_1(si);
    if (p.has_spec_trans) v.spec_trans = p.spec_trans->eval_1(si);
    if (p.has_sheen) v.sheen = p.sheen->eval_1(si);
    if (p.has_sheen_tint) v.sheen_tint = p.sheen_tint->eval_1(si);
    if (p.has_flatness) v.flatness = p.flatness->eval_1(si);
    if (p.has_spec_tint) v.spec_tint = p.spec_tint->eval_1(si);
    return v;
}

Color3 diffuse_term(const CommonValues& v, bool has_flatness, float cos_theta_i, float cos_theta_o,
                    float cos_theta_d) {
    const float abs_o = std::abs(cos_theta_o), abs_i = std::abs(cos_theta_i);
    const float Fo = schlick_weight(abs_o), Fi = schlick_weight(abs_i);
    const float f_diff = (1.f - 0.5f * Fi) * (1.f - 0.5f * Fo);
    const float Rr = 2.f * v.roughness * cos_theta_d * cos_theta_d;
    const float f_retro = Rr * (Fo + Fi + Fo * Fi * (Rr - 1.f));
    float shape = f_diff + f_retro;
    if (has_flatness) {
        // Hanrahan-Krueger-like fake subsurface, Fss90 flattening the retro-reflection.
        const float Fss90 = 0.5f * Rr;
        const float Fss = (1.f + (Fss90 - 1.f) * Fo) * (1.f + (Fss90 - 1.f) * Fi);
        const float f_ss = 1.25f * (Fss * (1.f / (abs_o + abs_i) - 0.5f) + 0.5f);
        shape = (1.f - v.flatness) * shape + v.flatness * f_ss;
    }
    return v.base_color * (abs_o * InvPi * shape);
}

Color3 sheen_term(const CommonValues& v, bool has_sheen_tint, float cos_theta_o, float cos_theta_d) {
    const float Fd = schlick_weight(std::abs(cos_theta_d));
    Color3 c_sheen(1.f);
    if (has_sheen_tint) c_sheen = Color3(1.f - v.sheen_tint) + tint_color(v.base_color) * v.sheen_tint;
    return c_sheen * (v.sheen * Fd * std::abs(cos_theta_o));
}

}  // namespace volguide::principled
