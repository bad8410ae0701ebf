#pragma once
// The closed form of transmittance through constant extinction, e^(-sigma t) per channel: the one
// every exact transmittance in the renderer uses (homogeneous media, the control variate of
// residual ratio tracking, volpath's spectral-MIS distance weights, the cache estimate's steps).
// sigma >= 0 (media reject negative extinction); an empty channel transmits everything, even to
// infinity (no 0 * inf = NaN).
#include <cmath>

#include "volguide/core/color.h"

namespace volguide {

inline float transmittance_1(float sigma, float t) { return sigma > 0.f ? std::exp(-sigma * t) : 1.f; }
inline Color3 transmittance_rgb(const Color3& sigma, float t) {
    return {transmittance_1(sigma.r, t), transmittance_1(sigma.g, t), transmittance_1(sigma.b, t)};
}

}  // namespace volguide
