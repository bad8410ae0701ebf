#include "volguide/render/bsdfs/microfacet.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "volguide/core/frame.h"
#include "volguide/core/warp.h"
#include "volguide/render/bsdfs/fresnel.h"
#include "volguide/render/texture.h"

namespace volguide {

namespace {
constexpr float InvSqrtPi = 0.56418958354775628695f;
}

float erfinv(float x) {
    // Giles, "Approximating the erfinv function" (GPU Gems 4), single precision variant.
    float w = -std::log(std::max((1.f - x) * (1.f + x), 1e-30f)), p;
    if (w < 5.f) {
        w -= 2.5f;
        p = 2.81022636e-08f;
        p = 3.43273939e-07f + p * w;
        p = -3.5233877e-06f + p * w;
        p = -4.39150654e-06f + p * w;
        p = 0.00021858087f + p * w;
        p = -0.00125372503f + p * w;
        p = -0.00417768164f + p * w;
        p = 0.246640727f + p * w;
        p = 1.50140941f + p * w;
    } else {
        w = std::sqrt(w) - 3.f;
        p = -0.000200214257f;
        p = 0.000100950558f + p * w;
        p = 0.00134934322f + p * w;
        p = -0.00367342844f + p * w;
        p = 0.00573950773f + p * w;
        p = -0.0076224613f + p * w;
        p = 0.00943887047f + p * w;
        p = 1.00167406f + p * w;
        p = 2.83297682f + p * w;
    }
    return p * x;
}

float MicrofacetDistribution::eval(const Vec3f& m) const {
    const float cos_theta = m.z, cos_theta_2 = cos_theta * cos_theta;
    float result;
    if (type_ == MicrofacetType::Beckmann) {
        result = std::exp(-(sqr(m.x / alpha_u_) + sqr(m.y / alpha_v_)) / cos_theta_2) /
                 (Pi * alpha_u_ * alpha_v_ * sqr(cos_theta_2));
    } else {
        result = 1.f / (Pi * alpha_u_ * alpha_v_ * sqr(sqr(m.x / alpha_u_) + sqr(m.y / alpha_v_) + sqr(m.z)));
    }
    // Mitsuba drops tiny values (and everything below the horizon) to avoid numerical trouble later.
    return result * cos_theta > 1e-20f ? result : 0.f;
}

float MicrofacetDistribution::pdf(const Vec3f& wi, const Vec3f& m) const {
    float result = eval(m);
    if (sample_visible_)
        result *= smith_g1(wi, m) * absdot(wi, m) / wi.z;
    else
        result *= m.z;
    return result;
}

float MicrofacetDistribution::smith_g1(const Vec3f& v, const Vec3f& m) const {
    const float xy_alpha_2 = sqr(alpha_u_ * v.x) + sqr(alpha_v_ * v.y);
    const float tan_theta_alpha_2 = xy_alpha_2 / sqr(v.z);
    float result;
    if (xy_alpha_2 == 0.f) {
        result = 1.f;  // perpendicular incidence: no shadowing
    } else if (type_ == MicrofacetType::Beckmann) {
        // Rational approximation of the Beckmann shadowing term (< 0.35% relative error).
        const float a = 1.f / std::sqrt(tan_theta_alpha_2), a2 = a * a;
        result = a >= 1.6f ? 1.f : (3.535f * a + 2.181f * a2) / (1.f + 2.276f * a + 2.577f * a2);
    } else {
        result = 2.f / (1.f + std::sqrt(1.f + tan_theta_alpha_2));
    }
    // The back of a microfacet is never visible from the front (and vice versa).
    if (dot(v, m) * v.z <= 0.f) result = 0.f;
    return result;
}

Vec2f MicrofacetDistribution::sample_visible_11(float cos_theta_i, Point2f u) const {
    if (type_ == MicrofacetType::Beckmann) {
        // Numerical inversion of the visible-slope CDF in the erf() domain (Jakob 2014), as Mitsuba.
        const float tan_theta_i = safe_sqrt(1.f - cos_theta_i * cos_theta_i) / cos_theta_i;
        const float cot_theta_i = 1.f / tan_theta_i;
        const float maxval = std::erf(cot_theta_i);
        u.x = std::clamp(u.x, 1e-6f, 1.f - 1e-6f);
        u.y = std::clamp(u.y, 1e-6f, 1.f - 1e-6f);
        float x = maxval - (maxval + 1.f) * std::erf(std::sqrt(-std::log(u.x)));
        u.x *= 1.f + maxval + InvSqrtPi * tan_theta_i * std::exp(-cot_theta_i * cot_theta_i);
        for (int i = 0; i < 3; ++i) {
            const float slope = erfinv(x);
            const float value = 1.f + x + InvSqrtPi * tan_theta_i * std::exp(-slope * slope) - u.x;
            const float derivative = 1.f - slope * tan_theta_i;
            x -= value / derivative;
        }
        return {erfinv(x), erfinv(2.f * u.y - 1.f)};
    }
    // GGX: Heitz 2017, "A Simpler and Exact Sampling Routine for the GGX Distribution of Visible Normals".
    Point2f p = warp::square_to_uniform_disk_concentric(u);
    const float s = 0.5f * (1.f + cos_theta_i);
    p.y = lerp(s, safe_sqrt(1.f - p.x * p.x), p.y);
    const float x = p.x, y = p.y, z = safe_sqrt(1.f - x * x - y * y);
    const float sin_theta_i = safe_sqrt(1.f - cos_theta_i * cos_theta_i);
    const float norm = 1.f / (sin_theta_i * y + cos_theta_i * z);
    return Vec2f(cos_theta_i * y - sin_theta_i * z, x) * norm;
}

std::pair<Vec3f, float> MicrofacetDistribution::sample(const Vec3f& wi, Point2f u) const {
    if (!sample_visible_) {
        float sin_phi, cos_phi, alpha_2;
        if (is_isotropic()) {
            const float phi = 2.f * Pi * u.y;
            sin_phi = std::sin(phi);
            cos_phi = std::cos(phi);
            alpha_2 = alpha_u_ * alpha_u_;
        } else {
            const float ratio = alpha_v_ / alpha_u_, tmp = ratio * std::tan(2.f * Pi * u.y);
            cos_phi = 1.f / std::sqrt(tmp * tmp + 1.f);
            cos_phi = std::copysign(cos_phi, std::abs(u.y - 0.5f) - 0.25f);
            sin_phi = cos_phi * tmp;
            alpha_2 = 1.f / (sqr(cos_phi / alpha_u_) + sqr(sin_phi / alpha_v_));
        }
        float cos_theta, pdf;
        if (type_ == MicrofacetType::Beckmann) {
            cos_theta = 1.f / std::sqrt(1.f - alpha_2 * std::log(1.f - u.x));
            const float cos_theta_3 = std::max(cos_theta * cos_theta * cos_theta, 1e-20f);
            pdf = (1.f - u.x) / (Pi * alpha_u_ * alpha_v_ * cos_theta_3);
        } else {
            const float tan_theta_m_2 = alpha_2 * u.x / (1.f - u.x);
            cos_theta = 1.f / std::sqrt(1.f + tan_theta_m_2);
            const float temp = 1.f + tan_theta_m_2 / alpha_2;
            const float cos_theta_3 = std::max(cos_theta * cos_theta * cos_theta, 1e-20f);
            pdf = 1.f / (Pi * alpha_u_ * alpha_v_ * cos_theta_3 * temp * temp);
        }
        const float sin_theta = safe_sqrt(1.f - cos_theta * cos_theta);
        return {Vec3f(cos_phi * sin_theta, sin_phi * sin_theta, cos_theta), pdf};
    }
    // 1. Stretch wi to the alpha = 1 configuration.
    const Vec3f wi_p = normalize(Vec3f(alpha_u_ * wi.x, alpha_v_ * wi.y, wi.z));
    const float sin_theta = Frame::sin_theta(wi_p);
    float sin_phi = 0.f, cos_phi = 1.f;
    if (sin_theta != 0.f) {
        sin_phi = std::clamp(wi_p.y / sin_theta, -1.f, 1.f);
        cos_phi = std::clamp(wi_p.x / sin_theta, -1.f, 1.f);
    }
    // 2. Sample the visible slopes of the unit-roughness distribution.
    Vec2f slope = sample_visible_11(wi_p.z, u);
    // 3. Rotate and unstretch.
    slope = Vec2f((cos_phi * slope.x - sin_phi * slope.y) * alpha_u_,
                  (sin_phi * slope.x + cos_phi * slope.y) * alpha_v_);
    // 4. Normal and density.
    const Vec3f m = normalize(Vec3f(-slope.x, -slope.y, 1.f));
    // Samples on the boundary of the square can map to an infinite slope (a horizontal normal of
    // zero density): report a failed sample instead of NaNs.
    if (!all_finite(m)) return {Vec3f(0.f, 0.f, 1.f), 0.f};
    const float pdf = eval(m) * smith_g1(wi, m) * absdot(wi, m) / wi.z;
    return {m, pdf};
}

MicrofacetParams MicrofacetParams::parse(const Properties& props) {
    MicrofacetParams p;
    if (props.has("distribution")) {
        std::string d = props.get_string("distribution");
        std::transform(d.begin(), d.end(), d.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (d == "beckmann")
            p.type = MicrofacetType::Beckmann;
        else if (d == "ggx")
            p.type = MicrofacetType::GGX;
        else
            props.fail_at("distribution", "invalid microfacet distribution '{}': must be 'beckmann' or 'ggx'",
                          d);
    }
    p.sample_visible = props.get_bool("sample_visible", true);
    auto check = [&](const std::string& name, const std::shared_ptr<Texture>& t) {
        // Constant roughness can be validated now; textures are clamped by the distribution.
        if (t->is_constant()) {
            Color3 v = t->mean();
            if (!v.is_finite() || v.has_negative())
                props.fail_at(name, "'{}' must be a finite value >= 0", name);
        }
    };
    if (props.has("alpha_u") || props.has("alpha_v")) {
        if (!props.has("alpha_u") || !props.has("alpha_v"))
            props.fail_here("microfacet model: both 'alpha_u' and 'alpha_v' must be specified");
        if (props.has("alpha"))
            props.fail_at("alpha", "microfacet model: specify either 'alpha' or 'alpha_u'/'alpha_v'");
        p.alpha_u = texture_param(props, "alpha_u");
        p.alpha_v = texture_param(props, "alpha_v");
        check("alpha_u", p.alpha_u);
        check("alpha_v", p.alpha_v);
        p.anisotropic = true;
    } else {
        p.alpha_u = p.alpha_v = texture_param(props, "alpha", Color3(0.1f));
        check("alpha", p.alpha_u);
    }
    if (p.alpha_u->is_constant() && p.alpha_v->is_constant()) {
        p.constant = true;
        p.const_alpha_u = p.alpha_u->mean().average();
        p.const_alpha_v = p.alpha_v->mean().average();
    }
    return p;
}

MicrofacetDistribution MicrofacetParams::at(const SurfaceInteraction& si) const {
    if (constant) return MicrofacetDistribution(type, const_alpha_u, const_alpha_v, sample_visible);
    return MicrofacetDistribution(type, alpha_u->eval_1(si), alpha_v->eval_1(si), sample_visible);
}

namespace {

// Gauss-Legendre nodes and weights on [-1, 1] (Newton iteration on the Legendre polynomial).
struct GaussLegendre {
    std::vector<double> nodes, weights;
    explicit GaussLegendre(int n) : nodes(n), weights(n) {
        for (int i = 0; i < n; ++i) {
            double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1.0, p1 = x;
                for (int k = 2; k <= n; ++k) {
                    double pk = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = pk;
                }
                dp = n * (x * p1 - p0) / (x * x - 1.0);
                double dx = p1 / dp;
                x -= dx;
                if (std::abs(dx) < 1e-15) break;
            }
            nodes[n - 1 - i] = x;
            weights[n - 1 - i] = 2.0 / ((1.0 - x * x) * dp * dp);
        }
    }
};

template <typename Integrand>
float integrate_visible_normals(const MicrofacetDistribution& distr, const Vec3f& wi, float eta,
                                Integrand f) {
    // Mitsuba uses 32 nodes per dimension for eta > 1 and 128 otherwise.
    const GaussLegendre gl(eta > 1.f ? 32 : 128);
    const int n = int(gl.nodes.size());
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            Point2f u(float(gl.nodes[i] * 0.5 + 0.5), float(gl.nodes[j] * 0.5 + 0.5));
            Vec3f m = distr.sample(wi, u).first;
            sum += double(f(m)) * gl.weights[i] * gl.weights[j] * 0.25;
        }
    return float(sum);
}

}  // namespace

float rough_reflectance(const MicrofacetDistribution& distr, const Vec3f& wi, float eta) {
    return integrate_visible_normals(distr, wi, eta, [&](const Vec3f& m) {
        Vec3f wo = reflect_about(wi, m);
        if (wo.z <= 0.f || wi.z <= 0.f) return 0.f;
        return distr.smith_g1(wo, m) * fresnel_dielectric(dot(wi, m), eta).F;
    });
}

float rough_transmittance(const MicrofacetDistribution& distr, const Vec3f& wi, float eta) {
    return integrate_visible_normals(distr, wi, eta, [&](const Vec3f& m) {
        FresnelResult fr = fresnel_dielectric(dot(wi, m), eta);
        Vec3f wo = refract_about(wi, m, fr.cos_theta_t, fr.eta_ti);
        if (wo.z * wi.z >= 0.f) return 0.f;
        return distr.smith_g1(wo, m) * (1.f - fr.F);
    });
}

}  // namespace volguide
