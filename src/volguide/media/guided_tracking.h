#pragma once
// Guided null-collision tracking (theory.md §7.7 "H2"; the null-scattering path integral of Miller
// et al. 2019, Kutz et al. 2017): tentative collisions at the majorant rate mu; at each one the
// caller chooses the probability P_s of scattering there, and the weight compensates per channel:
//   scatter:  w <- w * sigma_s(x) / (mu P_s),     continue:  w <- w * (mu - sigma_t(x)) / (mu (1 - P_s)).
// Absorption is folded into the weight (there is no absorption event). Unbiased for any P_s in
// [0, 1] as long as P_s > 0 wherever sigma_s > 0 and P_s < 1 wherever mu > sigma_t; the analog
// choice below is spectral tracking's (for grey media: delta tracking with weight = albedo).
#include <cmath>

#include "volguide/core/color.h"

namespace volguide {

// What the caller sees at a tentative collision.
struct TentativeCollision {
    float t;                // ray parameter
    float mu;               // the majorant-cell's rate (>= sigma_t in every channel for a true bound)
    Color3 sigma_t;         // true coefficients at ray(t)
    Color3 sigma_s;
    Color3 channel_weights;  // |throughput on entry x tracking weight so far|, normalised to sum 1
};

// The caller's side: P_s at each tentative collision, called in order of increasing t. A NaN is
// replaced by the analog probability, values outside [0, 1] are clamped.
class CollisionGuide {
public:
    virtual ~CollisionGuide() = default;
    virtual float scatter_probability(const TentativeCollision& c) = 0;
};

// Spectral tracking's scatter probability <|sigma_t q|> / (<|sigma_t q|> + <|sigma_n q|>), q the
// channel weights: it keeps the throughput-weighted channel sum of the path weight unchanged at
// every event, so chromatic weights stay bounded (a plain channel average would let the null
// weights of thin channels exceed 1 at every null collision).
inline float analog_scatter_probability(const TentativeCollision& c) {
    const Color3& q = c.channel_weights;
    float real = 0.f, null = 0.f;
    for (int ch = 0; ch < 3; ++ch) {
        real += std::abs(c.sigma_t[ch] * q[ch]);
        null += std::abs((c.mu - c.sigma_t[ch]) * q[ch]);
    }
    return real + null > 0.f ? real / (real + null) : 0.f;
}

}  // namespace volguide
