#include "volguide/integrators/guided/walk/vsp_distance.h"

#include <algorithm>
#include <cmath>

#include "volguide/core/math.h"
#include "volguide/media/homogeneous_transmittance.h"
#include "volguide/media/spectral_mis.h"

namespace volguide {

namespace {
// 1 - e^(-sigma s) without cancellation; 1 for an infinite segment through a non-empty channel.
float one_minus_transmittance(float sigma, float s) {
    if (!(sigma > 0.f)) return 0.f;
    return std::isinf(s) ? 1.f : -std::expm1(-sigma * s);
}
}  // namespace

HomogeneousVsp::HomogeneousVsp(const Color3& sigma_t, float s, const Color3& channel_shares)
    : sigma_t_(sigma_t), shares_(channel_shares), s_(s) {
    for (int c = 0; c < 3; ++c) absorbed_[c] = one_minus_transmittance(sigma_t[c], s);
    unguided_ = shares_.r * absorbed_.r + shares_.g * absorbed_.g + shares_.b * absorbed_.b;
    opaque_ = absorbed_.r == 1.f && absorbed_.g == 1.f && absorbed_.b == 1.f;
    if (opaque_) unguided_ = 1.f;  // the shares' sum may round below 1
}

float HomogeneousVsp::probability(float guided, float c) const {
    if (!(unguided_ > 0.f)) return 0.f;
    if (opaque_) return 1.f;
    if (std::isnan(guided)) return unguided_;
    const float p = c * unguided_ + (1.f - c) * std::clamp(guided, 0.f, 1.f);
    return std::clamp(p, 0.f, 1.f);
}

float HomogeneousVsp::conditional_pdf(float t) const {
    if (!(t >= 0.f && t < s_) || !(unguided_ > 0.f)) return 0.f;
    return spectral_distance_pdf(sigma_t_, shares_, t) / unguided_;
}

HomogeneousVsp::Sample HomogeneousVsp::sample(float P, float u_decide, float u_channel, float u_t) const {
    Sample out;
    if (!(u_decide < P)) {  // pass (P = 0 always passes, P = 1 never)
        out.t = s_;
        out.pdf = 1.f - P;
        out.flight_weight = out.pdf > 0.f ? transmittance_rgb(sigma_t_, s_) * (1.f / out.pdf) : Color3(0.f);
        return out;
    }
    // The channel with probability q_c (1 - T_c) / P_u, then its exponential truncated to (0, s).
    const Color3 channel = Color3(shares_.r * absorbed_.r, shares_.g * absorbed_.g, shares_.b * absorbed_.b) *
                           (1.f / unguided_);
    int c = sample_channel(channel, u_channel);
    if (!(absorbed_[c] > 0.f)) c = absorbed_.g > absorbed_[c] ? 1 : (absorbed_.r > absorbed_.b ? 0 : 2);  // round-off
    const float t = -std::log1p(-u_t * absorbed_[c]) / sigma_t_[c];
    out.scattered = true;
    out.t = std::min(t, std::nextafter(s_, 0.f));
    out.pdf = P * conditional_pdf(out.t);
    out.flight_weight = out.pdf > 0.f ? transmittance_rgb(sigma_t_, out.t) * (1.f / out.pdf) : Color3(0.f);
    return out;
}

}  // namespace volguide
