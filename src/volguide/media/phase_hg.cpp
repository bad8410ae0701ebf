#include "volguide/media/phase_hg.h"

#include <fmt/format.h>

#include "volguide/core/frame.h"

namespace volguide {

HGPhase::HGPhase(float g) : g_(std::clamp(g, -kMaxAbsG, kMaxAbsG)) {}

PhaseSample HGPhase::sample(const Vec3f& wi, Point2f u) const {
    // Sample the lobe for |g| about the axis a = -wi (g >= 0) or a = wi (g < 0); by symmetry
    // p_g(mu) = p_{-g}(-mu). With s = (1 - g^2) / (1 + g - 2 g u), the inverse CDF is
    // mu = (1 + g^2 - s^2) / (2 g); 1 - mu = (1 - g) u (s + 1 - g) / (1 + g - 2 g u) avoids the
    // cancellation near the peak that ruins strongly forward lobes in single precision.
    const float g = std::abs(g_);
    float one_minus_mu;
    if (g < 1e-4f) {
        one_minus_mu = 2.f * u.x;
    } else {
        const float denom = 1.f + g - 2.f * g * u.x;
        const float s = (1.f - g * g) / denom;
        one_minus_mu = (1.f - g) * u.x * (s + 1.f - g) / denom;
    }
    one_minus_mu = std::clamp(one_minus_mu, 0.f, 2.f);
    const float cos_theta = 1.f - one_minus_mu;
    const float sin_theta = safe_sqrt(one_minus_mu * (2.f - one_minus_mu));
    const float phi = 2.f * Pi * u.y;
    const Frame frame(g_ >= 0.f ? -wi : wi);
    PhaseSample ps;
    ps.wo = frame.to_world(spherical_direction(sin_theta, cos_theta, phi));
    ps.pdf = eval(wi, ps.wo);
    ps.weight = 1.f;
    return ps;
}

float HGPhase::eval(const Vec3f& wi, const Vec3f& wo) const {
    // 1 + g^2 - 2 g mu = (1 - g)^2 + 2 g (1 - mu) = (1 + g)^2 - 2 g (1 + mu), each a sum of
    // non-negative terms for the matching sign of g; 1 -/+ mu = |wo +/- wi|^2 / 2 for unit vectors.
    const float g = g_;
    float denom;
    if (g >= 0.f) {
        const float one_minus_mu = 0.5f * squared_norm(wo + wi);
        denom = sqr(1.f - g) + 2.f * g * one_minus_mu;
    } else {
        const float one_plus_mu = 0.5f * squared_norm(wo - wi);
        denom = sqr(1.f + g) - 2.f * g * one_plus_mu;
    }
    return InvFourPi * (1.f - g * g) / (denom * std::sqrt(denom));
}

std::string HGPhase::to_string() const { return fmt::format("HGPhase[g = {}]", g_); }

std::shared_ptr<PhaseFunction> make_hg_phase(const Properties& props) {
    const float g = props.get_float("g", 0.8f);
    if (!std::isfinite(g) || g <= -1.f || g >= 1.f)
        props.fail_at("g", "hg: the asymmetry parameter g must lie in (-1, 1) (got {})", g);
    return std::make_shared<HGPhase>(g);
}

}  // namespace volguide
