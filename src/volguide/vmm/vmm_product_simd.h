#pragma once
// The product lobes of two vMF mixtures four at a time (vmm_fast_product.h's product_fast, whose
// scalar loop this replaces at every guided medium vertex: issue 20's profile put the product at
// ~10 % of a guided sample in thin fog). Lanes are four lobes of the first mixture (the radiance
// VMM) against one lobe of the second (a phase VMM lobe); the closed form, the normalisations and
// the exponentials are those of product_lobe_fast and vmf_normalization_fast, with the kernels'
// four-lane exp (vmf_sum.h: within 2 ulp of expf, 0 below FLT_MIN) and a Taylor expm1, so results
// differ from the scalar ones by float rounding (test_vmm_fast_product compares them). A sampling
// mixture only shapes probabilities: its samples and pdf read the same values.
#include "volguide/core/vec.h"

namespace volguide {

// A mixture's lobes as arrays (a VmfMixture's fields): weight, mean direction, kappa, c~(kappa).
struct VmfLobeArrays {
    const float* weight;
    const float* mu_x;
    const float* mu_y;
    const float* mu_z;
    const float* kappa;
    const float* norm;
    int count;
};
struct VmfLobeOutput {
    float* weight;
    float* mu_x;
    float* mu_y;
    float* mu_z;
    float* kappa;
    float* norm;
};

// Writes lobe (k, j) of a x b to slot j * a.count + k of `out` (j-major: four lanes of k are stored
// together; product_into's order is k-major) with its scale (the weight before the
// exponential: a.weight[k] b.weight[j] c(kappa_a) c(kappa_b) / c(kappa_12)) and its exponent
// kappa_12 - kappa_a - kappa_b <= 0 to exponent[slot]; returns the largest exponent among the lobes
// of positive scale (-infinity if none). `out` and `exponent` hold at least a.count * b.count slots.
float product_lobes_simd(const VmfLobeArrays& a, const VmfLobeArrays& b, const VmfLobeOutput& out, float* exponent);

// weight[i] *= exp(exponent[i] - max_exponent) for i < n; returns the new weights' sum (float).
float scale_by_exponent_simd(float* weight, const float* exponent, int n, float max_exponent);

// The normalisation c~(kappa) of four lanes (vmf_normalization_fast's branches), for the tests.
void vmf_normalization_simd(const float kappa[4], float out[4]);

}  // namespace volguide
