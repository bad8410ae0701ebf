#pragma once
// One-sample spectral MIS for chromatic media (docs/theory.md §2.6): a free flight is sampled with one
// colour channel's extinction, chosen with probability proportional to the path throughput, and
// weighted per channel by (channel integrand) / (mixture density over the channels).
//
// Choosing the channel in proportion to the throughput (rather than uniformly) keeps the channel
// average of the throughput unchanged through every albedo-1 event: the weights stay bounded over
// long random walks instead of multiplying into a heavy tail.
#include <algorithm>
#include <cmath>

#include "volguide/core/color.h"
#include "volguide/core/math.h"
#include "volguide/media/homogeneous_transmittance.h"

namespace volguide {

// Channel-selection probabilities: |throughput| normalised; uniform when it carries nothing usable.
inline Color3 channel_probabilities(const Color3& throughput) {
    const Color3 a(std::abs(throughput.r), std::abs(throughput.g), std::abs(throughput.b));
    const float sum = a.r + a.g + a.b;
    if (!(sum > 0.f) || !std::isfinite(sum)) return Color3(1.f / 3.f);
    return a * (1.f / sum);
}

// Picks a channel from `probs` with u in [0, 1); u is rescaled to [0, 1) within the chosen
// channel so it can drive the distance sample.
inline int sample_channel(const Color3& probs, float& u) {
    float cdf = 0.f;
    for (int c = 0; c < 2; ++c) {
        const float p = probs[c];
        if (u < cdf + p && p > 0.f) {
            u = std::min((u - cdf) / p, OneMinusEpsilon);
            return c;
        }
        cdf += p;
    }
    const float p = probs[2];
    u = p > 0.f ? std::clamp((u - cdf) / p, 0.f, OneMinusEpsilon) : u;
    return 2;
}

// Density of the mixture of per-channel exponential free flights at t, and its probability of
// passing a distance s (homogeneous extinction sigma_t).
inline float spectral_distance_pdf(const Color3& sigma_t, const Color3& probs, float t) {
    const Color3 tr = transmittance_rgb(sigma_t, t);
    return probs.r * sigma_t.r * tr.r + probs.g * sigma_t.g * tr.g + probs.b * sigma_t.b * tr.b;
}
inline float spectral_escape_probability(const Color3& sigma_t, const Color3& probs, float s) {
    const Color3 tr = transmittance_rgb(sigma_t, s);
    return probs.r * tr.r + probs.g * tr.g + probs.b * tr.b;
}

}  // namespace volguide
