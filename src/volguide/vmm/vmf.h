#pragma once
// One von Mises-Fisher lobe on S^2 (docs/theory.md §3.1-3.5): density, sampling, mean cosine A3 and its
// inverse, the closed-form product of two lobes, and spherical convolution (exact value and the
// A3-product approximation). Parameters are stored in float; everything whose precision matters
// (normalisation, A3, products) is computed in double.
#include "volguide/core/frame.h"
#include "volguide/core/vec.h"

namespace volguide {

// Largest concentration any fit produces (Open PGL's cap, docs/theory.md §3.3). Products may exceed it.
inline constexpr float kVmfMaxKappa = 32000.f;
// Below this concentration a lobe is treated as the uniform sphere (error < 1e-6 relative).
inline constexpr float kVmfUniformKappa = 1e-6f;

// Stable normaliser c~(kappa) = kappa / (2 pi (1 - exp(-2 kappa))), so that the density is
// c~ * exp(kappa (cos - 1)); c~(0) = 1/(4 pi). Never forms sinh or exp(+kappa).
double vmf_normalization(double kappa);

// Mean cosine A3(kappa) = coth(kappa) - 1/kappa = E[mu . w] and its derivative.
double vmf_mean_cosine(double kappa);
double vmf_mean_cosine_derivative(double kappa);
// Banerjee et al. 2005 closed-form start, r (3 - r^2) / (1 - r^2) (docs/theory.md eq. 3.2).
double vmf_kappa_banerjee(double mean_cosine);
// Exact inverse of A3 (Banerjee start + safeguarded Newton). r <= 0 gives 0; r is clamped to
// A3(max_kappa), so the result is in [0, max_kappa].
double vmf_kappa_from_mean_cosine(double mean_cosine, double max_kappa = kVmfMaxKappa);

// 1 - cos(angle between a and b) computed as |a - b|^2 / 2: relative (not absolute) error for
// nearly parallel directions, which keeps kappa * (1 - cos) accurate up to kappa = 32000 in float.
inline float one_minus_cos(const Vec3f& a, const Vec3f& b) {
    return std::min(0.5f * squared_norm(a - b), 2.f);
}

// Invariant: norm == c~(kappa). The constructor and the mixtures' set_lobe keep it; code that
// assigns kappa directly must refresh norm too.
struct VmfLobe {
    Vec3f mu{0.f, 0.f, 1.f};  // mean direction (unit)
    float kappa = 0.f;        // concentration >= 0
    float norm = InvFourPi;   // c~(kappa), cached

    VmfLobe() = default;
    VmfLobe(const Vec3f& mean, float concentration)
        : mu(mean), kappa(concentration), norm(float(vmf_normalization(concentration))) {}

    // Density w.r.t. solid angle (the lobe is normalised, so eval == pdf).
    float eval(const Vec3f& w) const { return norm * std::exp(-kappa * one_minus_cos(mu, w)); }
    float pdf(const Vec3f& w) const { return eval(w); }
    // Jakob 2012 stable inversion; u in [0,1)^2.
    Vec3f sample(Point2f u) const;
    float mean_cosine() const { return float(vmf_mean_cosine(kappa)); }
};

// Samples 1 - cos(theta) about the lobe axis (the part of Jakob's method that needs care).
float vmf_sample_one_minus_cos(float kappa, float u);

// v(w|a) v(w|b) = scale * v(w|lobe) (docs/theory.md eq. 3.3); scale = integral of the product over S^2.
struct VmfProduct {
    VmfLobe lobe;
    double scale = 0.0;
};
VmfProduct vmf_product(const VmfLobe& a, const VmfLobe& b);
// (1 - cos, 1 + cos) of the angle between two unit axes, in double: the part of a product that
// depends only on the axes, so products of one lobe with several lobes on a common axis (a phase
// VMM's lobes all sit on +-the travel direction) compute it once.
struct VmfCosPair {
    double one_minus = 0.0, one_plus = 2.0;
};
VmfCosPair vmf_cos_pair(const Vec3f& a, const Vec3f& b);
// vmf_product(a, b) with c = vmf_cos_pair(a.mu, b.mu) (bit for bit the same result).
VmfProduct vmf_product(const VmfLobe& a, const VmfLobe& b, const VmfCosPair& c);

// Exact spherical convolution of two vMF lobes evaluated at angle theta between their axes:
// integral of v(w|mu1,k1) v(w|mu2,k2) dw with 1 - cos(theta) = one_minus_cos (eq. 3.4).
double vmf_convolution_exact(double kappa1, double kappa2, double one_minus_cos);
// Concentration of the single-lobe approximation of a convolution: A3^-1(A3(k1) A3(k2)) (eq. 3.5).
float vmf_convolved_kappa(float kappa1, float kappa2);

}  // namespace volguide
