#include "volguide/vmm/vmf.h"

#include <algorithm>
#include <cmath>

namespace volguide {

namespace {
// From here on expm1(-2 kappa) == -1 exactly (see vmf_normalization; test_vmf_lobe checks it).
constexpr double kNormalizationSaturates = 20.0;
}

double vmf_normalization(double kappa) {
    if (kappa < 1e-4) {
        // c~ = (1 + k + k^2/3 + O(k^4)) / (4 pi); the series avoids 0/0 at kappa = 0.
        return (1.0 + kappa + kappa * kappa / 3.0) / (4.0 * PiDouble);
    }
    // expm1(-2 kappa) rounds to exactly -1 in double once exp(-2 kappa) < 2^-54 (2 kappa > 37.4;
    // glibc returns -1 outright below -56 ln 2): the same value without the call, which matters
    // because every product lobe of a guided direction sampler normalises here (bench_vmm).
    if (kappa >= kNormalizationSaturates) return kappa / (2.0 * PiDouble);
    return kappa / (-2.0 * PiDouble * std::expm1(-2.0 * kappa));
}

double vmf_mean_cosine(double kappa) {
    if (kappa < 0.02) {
        // coth(k) - 1/k cancels for small k; the series is exact to ~1e-16 here.
        double k2 = kappa * kappa;
        return kappa * (1.0 / 3.0 - k2 / 45.0 + 2.0 * k2 * k2 / 945.0 - k2 * k2 * k2 / 4725.0);
    }
    // coth(k) = (1 + e) / (1 - e) with e = exp(-2k) <= 1: no overflow.
    double e = std::exp(-2.0 * kappa);
    return (1.0 + e) / (-std::expm1(-2.0 * kappa)) - 1.0 / kappa;
}

double vmf_mean_cosine_derivative(double kappa) {
    // A3'(k) = 1/k^2 - 1/sinh^2(k); the difference cancels for small k, so use the series there.
    if (kappa < 0.05) {
        double k2 = kappa * kappa;
        return 1.0 / 3.0 - k2 / 15.0 + 2.0 * k2 * k2 / 189.0 - k2 * k2 * k2 / 675.0;
    }
    double e = std::exp(-2.0 * kappa);
    double one_minus_e = -std::expm1(-2.0 * kappa);
    return 1.0 / (kappa * kappa) - 4.0 * e / (one_minus_e * one_minus_e);
}

namespace {
// A3 and A3' together from a single expm1 (the Newton loop's inner step).
void mean_cosine_and_derivative(double k, double& a3, double& d) {
    if (k < 0.05) {
        a3 = vmf_mean_cosine(k);
        d = vmf_mean_cosine_derivative(k);
        return;
    }
    double em1 = std::expm1(-2.0 * k), one_minus_e = -em1, e = 1.0 + em1;
    a3 = (1.0 + e) / one_minus_e - 1.0 / k;
    d = 1.0 / (k * k) - 4.0 * e / (one_minus_e * one_minus_e);
}
}  // namespace

double vmf_kappa_banerjee(double r) {
    r = std::clamp(r, 0.0, 1.0 - 1e-12);
    return r * (3.0 - r * r) / (1.0 - r * r);
}

double vmf_kappa_from_mean_cosine(double r, double max_kappa) {
    if (!(r > 0.0)) return 0.0;  // also maps NaN to 0
    const double r_max = vmf_mean_cosine(max_kappa);
    if (r >= r_max) return max_kappa;
    if (r < 1e-5) return 3.0 * r;  // A3(k) = k/3 + O(k^3)
    // A3 is increasing: keep a bracket [lo, hi] and fall back to bisection when Newton leaves it.
    double lo = 0.0, hi = max_kappa;
    double k = std::min(vmf_kappa_banerjee(r), max_kappa);
    // A3 is only known to ~1e-16 absolute and A3' ~ 1/k^2, so k is determined to ~1e-16 k^2:
    // stop when the residual reaches that noise or the step is below 1e-12 relative.
    for (int it = 0; it < 40; ++it) {
        double a3, d;
        mean_cosine_and_derivative(k, a3, d);
        double f = a3 - r;
        if (std::abs(f) <= 2e-16) return k;
        if (f > 0.0)
            hi = k;
        else
            lo = k;
        double step = f / d;
        double next = k - step;
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::abs(next - k) <= 1e-12 * k) return next;
        k = next;
    }
    return k;
}

float vmf_sample_one_minus_cos(float kappa, float u) {
    if (kappa < kVmfUniformKappa) return 2.f * u;
    // t = 1 - cos = -log(1 - u (1 - exp(-2k))) / k, in [0, 2]; log1p/expm1 keep it accurate for
    // small k, and for large k exp(-2k) -> 0 only makes the argument of log1p approach -1 (u < 1).
    float t = -std::log1p(u * std::expm1(-2.f * kappa)) / kappa;
    return std::clamp(t, 0.f, 2.f);
}

Vec3f VmfLobe::sample(Point2f u) const {
    float t = vmf_sample_one_minus_cos(kappa, u.x);
    // sin(theta) from t directly: computing 1 - cos first would lose precision at high kappa.
    float sin_theta = std::sqrt(std::max(t * (2.f - t), 0.f));
    float phi = 2.f * Pi * u.y;
    Vec3f local(sin_theta * std::cos(phi), sin_theta * std::sin(phi), 1.f - t);
    return Frame(mu).to_world(local);
}

namespace {
// c~(kappa) for product lobes. Where 1 - exp(-2 kappa) >= 0.39 (kappa >= 0.25) it has no
// cancellation, and glibc's exp is cheaper than its expm1 (bench/RESULTS.md (issue 35)): the value differs
// from vmf_normalization's by double rounding only (the float lobe.norm by none in a 1000-point
// sweep).
double product_normalization(double kappa) {
    if (kappa >= 0.25 && kappa < kNormalizationSaturates) return kappa / (2.0 * PiDouble * (1.0 - std::exp(-2.0 * kappa)));
    return vmf_normalization(kappa);
}

// kappa12 = |k1 mu1 + k2 mu2| and (kappa12 - k1 - k2) <= 0 without cancellation.
void product_kappa(double k1, double k2, double one_minus, double one_plus, double& k12, double& exponent) {
    k12 = std::sqrt((k1 - k2) * (k1 - k2) + 2.0 * k1 * k2 * one_plus);
    double denom = k12 + k1 + k2;
    exponent = denom > 0.0 ? -2.0 * k1 * k2 * one_minus / denom : 0.0;
}
}  // namespace

VmfCosPair vmf_cos_pair(const Vec3f& a, const Vec3f& b) {
    // Both from vector differences, so that neither suffers from cancellation; they sum to 2.
    const Vec3d m1(a), m2(b);
    double dm = squared_norm(m1 - m2), dp = squared_norm(m1 + m2);
    double s = dm + dp;
    return {2.0 * dm / s, 2.0 * dp / s};
}

VmfProduct vmf_product(const VmfLobe& a, const VmfLobe& b) { return vmf_product(a, b, vmf_cos_pair(a.mu, b.mu)); }

VmfProduct vmf_product(const VmfLobe& a, const VmfLobe& b, const VmfCosPair& c) {
    double k1 = a.kappa, k2 = b.kappa;
    Vec3d m1(a.mu), m2(b.mu);
    double k12, exponent;
    product_kappa(k1, k2, c.one_minus, c.one_plus, k12, exponent);

    VmfProduct p;
    Vec3d m = m1 * k1 + m2 * k2;
    double m_norm = norm(m);
    double norm12;
    if (k12 < kVmfUniformKappa || !(m_norm > 0.0)) {
        // Uniform product (e.g. equal antipodal lobes): the axis is arbitrary, keep mu1.
        k12 = 0.0;
        p.lobe = VmfLobe(a.mu, 0.f);
        norm12 = vmf_normalization(0.0);
    } else {
        norm12 = product_normalization(k12);
        p.lobe.mu = Vec3f(m / m_norm);
        p.lobe.kappa = float(k12);
        p.lobe.norm = float(norm12);
    }
    // The inputs' cached c~ (float, 1e-7 relative) saves two expm1 per product; c~(k12) is computed
    // once, in double, for both the lobe and the scale.
    p.scale = double(a.norm) * double(b.norm) / norm12 * std::exp(exponent);
    return p;
}

double vmf_convolution_exact(double kappa1, double kappa2, double one_minus_cos) {
    double one_minus = std::clamp(one_minus_cos, 0.0, 2.0);
    double k12, exponent;
    product_kappa(kappa1, kappa2, one_minus, 2.0 - one_minus, k12, exponent);
    return vmf_normalization(kappa1) * vmf_normalization(kappa2) / vmf_normalization(k12) *
           std::exp(exponent);
}

float vmf_convolved_kappa(float kappa1, float kappa2) {
    double r = vmf_mean_cosine(kappa1) * vmf_mean_cosine(kappa2);
    double cap = std::max({double(kappa1), double(kappa2), double(kVmfMaxKappa)});
    return float(vmf_kappa_from_mean_cosine(r, cap));
}

}  // namespace volguide
