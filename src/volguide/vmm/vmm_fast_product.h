#pragma once
// Products of a vMF mixture with one lobe in single precision, for the surface guide built at every
// diffuse surface vertex (docs/theory.md §3.4 / §3.6; the medium vertices' mixture x phase product is
// lobe_product.h's). The double-precision product_into (vmm.h) is
// the reference; this one computes the same closed form in float with a float normalisation,
// several times cheaper (bench/RESULTS.md (issue 35)), to about 1e-6 relative in the weights away from
// the extremes (the test sweeps kappa in [0, 32000]). A sampling mixture only has to be a
// normalised mixture whose samples
// and pdf agree: its values shape probabilities and never enter weights directly.
#include <array>
#include <cmath>

#include "volguide/vmm/vmm.h"

namespace volguide {

// c~(kappa) in float (vmf.h eq. 3.1): the series below 1e-3, exp where 1 - e^{-2 kappa} does not
// cancel, expm1 between, and kappa / 2 pi once e^{-2 kappa} is below float epsilon.
inline float vmf_normalization_fast(float kappa) {
    constexpr float inv_4pi = 0.0795774715459476679f, inv_2pi = 0.159154943091895336f;
    if (kappa < 1e-3f) return (1.f + kappa + kappa * kappa * (1.f / 3.f)) * inv_4pi;
    if (kappa >= 9.f) return kappa * inv_2pi;  // e^{-18} < FLT_EPSILON / 2
    const float denom = kappa >= 0.25f ? 1.f - std::exp(-2.f * kappa) : -std::expm1(-2.f * kappa);
    return kappa * inv_2pi / denom;
}

// 1 - cos of two unit vectors from their difference: no cancellation near cos = 1.
inline float one_minus_cos_fast(float ax, float ay, float az, const Vec3f& b) {
    const float dx = ax - b.x, dy = ay - b.y, dz = az - b.z;
    return std::fmin(0.5f * (dx * dx + dy * dy + dz * dz), 2.f);
}

// The product lobe of lobe k of `a` with `b` (one_minus = 1 - mu_a . mu_b): writes it to out slot
// `slot` with weight a.weight[k] * c(kappa_a) c(kappa_b) / c(kappa_12) (the scale without its
// exponential) and returns the exponent kappa_12 - kappa_a - kappa_b <= 0 (docs/theory.md eq. 3.3).
template <int A, int C>
float product_lobe_fast(const VmfMixture<A>& a, int k, const VmfLobe& b, float one_minus, VmfMixture<C>& out,
                        int slot) {
    const float ka = a.kappa[k], kb = b.kappa;
    const float ax = a.mu_x[k], ay = a.mu_y[k], az = a.mu_z[k];
    const float one_plus = 2.f - one_minus;
    const float k12 = std::sqrt((ka - kb) * (ka - kb) + 2.f * ka * kb * one_plus);
    const float denom = k12 + ka + kb;
    const float exponent = denom > 0.f ? -2.f * ka * kb * one_minus / denom : 0.f;
    const float mx = ka * ax + kb * b.mu.x, my = ka * ay + kb * b.mu.y, mz = ka * az + kb * b.mu.z;
    const float m_norm = std::sqrt(mx * mx + my * my + mz * mz);
    float norm12;
    if (k12 < kVmfUniformKappa || !(m_norm > 0.f)) {
        norm12 = vmf_normalization_fast(0.f);
        out.mu_x[slot] = ax;
        out.mu_y[slot] = ay;
        out.mu_z[slot] = az;
        out.kappa[slot] = 0.f;
    } else {
        norm12 = vmf_normalization_fast(k12);
        const float inv = 1.f / m_norm;
        out.mu_x[slot] = mx * inv;
        out.mu_y[slot] = my * inv;
        out.mu_z[slot] = mz * inv;
        out.kappa[slot] = k12;
    }
    out.norm[slot] = norm12;
    out.weight[slot] = a.weight[k] * (a.norm[k] * b.norm / norm12);
    return exponent;
}

// The products' last step: lobe i's weight (its scale) times exp(exponent[i] - max_exponent), the
// n lobes normalised to sum 1 and out.count set to n; returns Z = the scales' sum times
// exp(max_exponent), in double (0, out empty: no finite positive mass).
template <int C>
double normalize_product_fast(VmfMixture<C>& out, int n, const float* exponent, float max_exponent) {
    out.count = 0;
    if (!std::isfinite(max_exponent)) return 0.0;
    float z = 0.f;
    for (int i = 0; i < n; ++i) {
        out.weight[i] *= std::exp(exponent[i] - max_exponent);
        z += out.weight[i];
    }
    if (!(z > 0.f) || !std::isfinite(z)) return 0.0;
    out.count = n;
    const float inv = 1.f / z;
    for (int i = 0; i < n; ++i) out.weight[i] *= inv;
    return double(z) * std::exp(double(max_exponent));
}

// out = a(w) b(w) / Z with Z = integral of a b; returns Z in double (0: out is empty, nothing to
// sample). The lobes' exponentials are taken relative to the largest, so a product whose every
// lobe is far below float range (two concentrated, distant lobes) keeps its shape.
template <int A, int C>
double product_with_lobe_fast(const VmfMixture<A>& a, const VmfLobe& b, VmfMixture<C>& out) {
    static_assert(C >= A, "product_with_lobe_fast: output capacity below the input's");
    std::array<float, A> exponent;
    float max_exponent = -INFINITY;
    for (int k = 0; k < a.count; ++k) {
        const float omc = one_minus_cos_fast(a.mu_x[k], a.mu_y[k], a.mu_z[k], b.mu);
        exponent[k] = product_lobe_fast(a, k, b, omc, out, k);
        if (out.weight[k] > 0.f) max_exponent = std::fmax(max_exponent, exponent[k]);
    }
    return normalize_product_fast(out, a.count, exponent.data(), max_exponent);
}

}  // namespace volguide
