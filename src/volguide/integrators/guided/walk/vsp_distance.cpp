#include "volguide/integrators/guided/walk/vsp_distance.h"

#include <algorithm>
#include <cmath>

#include "volguide/core/math.h"
#include "volguide/integrators/volpath/equiangular_mis.h"
#include "volguide/render/scene.h"
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

std::optional<EquiangularSampler> vsp_equiangular_toward_light(const Scene& scene, const Ray& ray, float s,
                                                               Sampler& sampler) {
    Interaction origin;
    origin.p = ray.o;
    const DirectionSample y = scene.sample_emitter_direction(origin, sampler.next_2d(), false).first;
    if (!(y.pdf > 0.f) || !equiangular_target(y.emitter) || !std::isfinite(y.dist)) return std::nullopt;
    EquiangularSampler eq(ray.o, ray.d, s, y.p);
    if (!eq.valid()) return std::nullopt;
    return eq;
}

float HomogeneousVsp::conditional_pdf(float t, const VspEquiangular& equi) const {
    const float ff = conditional_pdf(t);
    if (!equi.active() || !(t >= 0.f && t < s_) || !(unguided_ > 0.f)) return ff;
    return (1.f - equi.share) * ff + equi.share * equi.sampler->pdf(t);
}

HomogeneousVsp::Sample HomogeneousVsp::sample(float P, float u_decide, float u_channel, float u_t,
                                              const VspEquiangular& equi) const {
    Sample out;
    if (!(u_decide < P)) {  // pass (P = 0 always passes, P = 1 never)
        out.t = s_;
        out.pdf = 1.f - P;
        out.flight_weight = out.pdf > 0.f ? transmittance_rgb(sigma_t_, s_) * (1.f / out.pdf) : Color3(0.f);
        return out;
    }
    out.scattered = true;
    if (equi.active() && u_channel < equi.share) {  // the equiangular strategy
        out.t = std::min(equi.sampler->sample(u_t), std::nextafter(s_, 0.f));
    } else {
        if (equi.active()) u_channel = std::min((u_channel - equi.share) / (1.f - equi.share), OneMinusEpsilon);
        out.t = truncated_free_flight(u_channel, u_t);
    }
    out.pdf = P * conditional_pdf(out.t, equi);
    out.flight_weight = out.pdf > 0.f ? transmittance_rgb(sigma_t_, out.t) * (1.f / out.pdf) : Color3(0.f);
    return out;
}

float HomogeneousVsp::truncated_free_flight(float u_channel, float u_t) const {
    // The channel with probability q_c (1 - T_c) / P_u, then its exponential truncated to (0, s).
    const Color3 channel = Color3(shares_.r * absorbed_.r, shares_.g * absorbed_.g, shares_.b * absorbed_.b) *
                           (1.f / unguided_);
    int c = sample_channel(channel, u_channel);
    if (!(absorbed_[c] > 0.f)) c = absorbed_.g > absorbed_[c] ? 1 : (absorbed_.r > absorbed_.b ? 0 : 2);  // round-off
    const float t = -std::log1p(-u_t * absorbed_[c]) / sigma_t_[c];
    return std::min(t, std::nextafter(s_, 0.f));
}

namespace {
// |w| weighted by the channel shares q: the scalar a candidate is resampled by.
float shared_magnitude(const Color3& w, const Color3& q) {
    return q.r * std::abs(w.r) + q.g * std::abs(w.g) + q.b * std::abs(w.b);
}
}  // namespace

FreeFlightSample resampled_segment_flight(const Medium& medium, const Ray& ray, float tmax, const Color3& throughput,
                                          const SegmentProbability& probability, Sampler& sampler) {
    const Color3 q = channel_probabilities(throughput);
    // The walk: ratio tracking's T^ before each collision, and a one-slot reservoir over the scatter
    // candidates w_i = T^_i sigma_s(t_i) / mu_i by |w_i|_q.
    Color3 tr(1.f);
    float total = 0.f;  // sum of |w_i|_q
    struct Slot {
        float t = 0.f, mu = 0.f, magnitude = 0.f;
        Color3 sigma_t{0.f}, tr{0.f};
    } slot;
    medium.sample_majorant_walk(ray, tmax, sampler, [&](const MajorantCollision& c) {
        const Color3 sigma_s = c.sigma_t * medium.albedo(ray(c.t));
        const float m = shared_magnitude(tr * sigma_s, q) / c.mu;
        if (m > 0.f) {
            total += m;
            if (sampler.next_1d() * total < m) slot = {c.t, c.mu, m, c.sigma_t, tr};
        }
        tr *= Color3(1.f) - c.sigma_t * (1.f / c.mu);
        return !tr.is_black();  // T^ = 0: nothing passes and the candidates beyond carry nothing
    });
    // The decision: scatter (one of the candidates) with P, pass with 1 - P.
    const float pass = shared_magnitude(tr, q);
    float P = probability(std::clamp(1.f - pass, 0.f, 1.f));
    if (!(total > 0.f)) P = 0.f;
    else if (!(pass > 0.f)) P = 1.f;
    else P = std::clamp(P, kResampledMinProbability, 1.f - kResampledMinProbability);
    FreeFlightSample fs;
    fs.t = tmax;
    if (!(sampler.next_1d() < P)) {
        fs.weight = fs.flight_weight = P < 1.f ? tr * (1.f / (1.f - P)) : Color3(0.f);
        return fs;
    }
    // The kept candidate's selection probability pi_k = |w_k|_q / total.
    const float pi = slot.magnitude / total;
    const Point3f p = ray(slot.t);
    fs.scatter_at(ray, slot.t, p, &medium, {slot.sigma_t, slot.sigma_t * medium.albedo(p)});
    // w_k / (P pi_k), without sigma_s for the flight weight.
    fs.flight_weight = pi > 0.f ? slot.tr * (1.f / (slot.mu * pi * P)) : Color3(0.f);
    fs.weight = fs.flight_weight * fs.mi.coeffs.sigma_s;
    return fs;
}

}  // namespace volguide
