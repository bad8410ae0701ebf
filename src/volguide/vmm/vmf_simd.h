#pragma once
// The vectorised vMF kernels of the render-time decisions (docs/theory.md §3.7), over lobe blocks
// (lobe_block.h), kLobeLanes lobes at a time. Google Highway (Debian's libhwy-dev) compiles them for
// every x86 target it knows (SSSE3, SSE4, AVX2, AVX-512) and picks the best the CPU has at the first
// call (runtime dispatch), with its vector exp; vmf_simd.cpp is the only file that includes Highway.
// Sums of exponentials come as (sum, max exponent), value = sum x e^max, so that lobes far below
// float range keep their ratios.
#include "volguide/core/vec.h"
#include "volguide/vmm/lobe_block.h"

namespace volguide {

struct ScaledSum {
    float sum = 0.f;                  // 0: no lobe with mass
    float max_exponent = -INFINITY;  // the largest exponent among the lobes with mass
    // The value, sum x e^max (0 where it underflows).
    float value() const { return sum > 0.f ? sum * std::exp(max_exponent) : 0.f; }
};

// sum_k scale_k exp(-kappa_k (1 - mu_k . w)) of block b: the mixture's density at w.
ScaledSum lobe_block_eval(const LobeBlock& b, const Vec3f& w);

// The phase lobes a product pairs each leaf lobe with: J lobes on sign_j x d (d the travel direction).
struct PairedLobes {
    int count = 0;
    const float* kappa = nullptr;
    const float* scale = nullptr;  // weight x c~(kappa)
    const float* sign = nullptr;   // +1 or -1
};

// The products v_k v_j of each lobe k of `leaf` with each lobe j of `phase` (theory eq. 3.3 in closed
// form: one sqrt, one division, two exponentials per pair): pair (k, j) at j x leaf.padded + k gets
// its mass relative to the largest, mass = scale_k scale_j / c~(kappa_12) e^(E_kj - E_max) (0 for pad
// lanes), its kappa_12 and expm1(-2 kappa_12). Returns (sum of the masses, E_max): the product's
// integral Z is sum x e^E_max.
ScaledSum lobe_product_pairs(const LobeBlock& leaf, const PairedLobes& phase, const Vec3f& d, float* mass,
                             float* kappa12, float* expm1_2k12);

}  // namespace volguide
