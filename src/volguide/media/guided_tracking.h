#pragma once
// Guided null-collision tracking (docs/theory.md §7.7 "H2"; the null-scattering path integral of Miller
// et al. 2019, Kutz et al. 2017): tentative collisions at the majorant rate mu; at each one the
// caller chooses the probability P_s of scattering there, and the weight compensates per channel:
//   scatter:  w <- w * sigma_s(x) / (mu P_s),     continue:  w <- w * (mu - sigma_t(x)) / (mu (1 - P_s)).
// Absorption is folded into the weight (there is no absorption event). Unbiased for any P_s in
// [0, 1] as long as P_s > 0 wherever sigma_s > 0 and P_s < 1 wherever mu > sigma_t; the unguided
// choice below is spectral tracking's (for grey media: delta tracking with weight = albedo).
#include <cmath>

#include "volguide/core/color.h"

namespace volguide {

// A tentative collision: what the walk's decision there (collision_policy.h) and a guided
// scatter probability (majorant_tracking.h's guided_tracking) see.
struct TentativeCollision {
    float t;                // ray parameter
    float mu;               // the majorant-cell's rate (>= sigma_t in every channel for a true bound)
    Color3 sigma_t;         // true coefficients at ray(t)
    Color3 sigma_s;         // (a walk whose decision does not read it fills it in at the scatter only)
    // The path's channel weights q: throughput on entry (as channel probabilities) x tracking weight
    // so far. A guided scatter probability sees them as |q| normalised to sum 1.
    Color3 channel_weights;
};

// Spectral tracking (Kutz et al. 2017) weighs the two events of a tentative collision by their
// channel sums over the channel weights q: real = sum |sigma_t q|, null = sum |sigma_n q| with
// sigma_n = mu - sigma_t (with absolute values it stays unbiased where mu < sigma_t).
struct SpectralTrackingWeights {
    float real, null;
};
inline SpectralTrackingWeights spectral_tracking_weights(const TentativeCollision& c) {
    const Color3& q = c.channel_weights;
    SpectralTrackingWeights s{0.f, 0.f};
    for (int ch = 0; ch < 3; ++ch) {
        s.real += std::abs(c.sigma_t[ch] * q[ch]);
        s.null += std::abs((c.mu - c.sigma_t[ch]) * q[ch]);
    }
    return s;
}

// Spectral tracking's scatter probability real / (real + null): it keeps the throughput-weighted
// channel sum of the path weight unchanged at every event, so chromatic weights stay bounded (a
// plain channel average would let the null weights of thin channels exceed 1 at every null
// collision).
inline float unguided_scatter_probability(const TentativeCollision& c) {
    const SpectralTrackingWeights s = spectral_tracking_weights(c);
    return s.real + s.null > 0.f ? s.real / (s.real + s.null) : 0.f;
}

}  // namespace volguide
