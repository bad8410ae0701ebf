// vMF lobe identities (docs/theory.md §3.1-3.5, §14.1-14.4): normalisation by quadrature, A3 and its
// inverse, the closed-form product, exact and approximate convolution, and robustness at the
// ends of the kappa range.
#include <gtest/gtest.h>

#include "support/sphere_quadrature.h"
#include "volguide/vmm/vmf.h"

using namespace volguide;
using volguide::test::integrate_sphere;

namespace {
// Double-precision density, for identities whose values underflow float (e.g. 1e-91).
double eval_d(const VmfLobe& l, const Vec3f& w) {
    return vmf_normalization(l.kappa) *
           std::exp(-double(l.kappa) * 0.5 * squared_norm(Vec3d(w) - Vec3d(l.mu)));
}
const Vec3f kAxis = normalize(Vec3f(0.3f, -0.5f, 0.81f));

double peak_scale(double kappa) {
    return kappa > 1.0 ? 1.0 / std::sqrt(kappa) : M_PI;
}

// Direction at angle theta from `axis`, rotated about it by phi.
Vec3f rotate_away(const Vec3f& axis, double theta, double phi = 0.7) {
    Frame f(axis);
    return normalize(f.to_world(Vec3f(float(std::sin(theta) * std::cos(phi)),
                                      float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)))));
}
}  // namespace

// vmf_normalization skips expm1 once it saturates (kappa >= 20): the value must be the formula's,
// bit for bit, so that guided images do not change (expm1(-2 kappa) is exactly -1 there).
TEST(VmfLobe, NormalisationShortcutIsExact) {
    for (double kappa = 19.0; kappa < 1e6; kappa *= 1.0 + 1e-4) {
        const double formula = kappa / (-2.0 * M_PI * std::expm1(-2.0 * kappa));
        ASSERT_EQ(vmf_normalization(kappa), formula) << "kappa " << kappa;
    }
}

// The product with a precomputed angle is the product (product_into shares it over phase lobes).
TEST(VmfLobe, ProductWithSharedAngleIsIdentical) {
    const VmfLobe a(kAxis, 37.f);
    for (float kappa : {0.5f, 3.f, 14.f, 101.f}) {
        const VmfLobe b(rotate_away(kAxis, 0.9), kappa);
        const VmfProduct p = vmf_product(a, b), q = vmf_product(a, b, vmf_cos_pair(a.mu, b.mu));
        EXPECT_EQ(p.scale, q.scale);
        EXPECT_EQ(p.lobe.kappa, q.lobe.kappa);
        EXPECT_EQ(p.lobe.norm, q.lobe.norm);
        EXPECT_EQ(p.lobe.mu, q.lobe.mu);
    }
}

// Product lobes normalise with exp instead of expm1 where that has no cancellation (kappa in
// [0.25, 20)): the invariant norm == c~(kappa) must hold to float rounding across that range.
TEST(VmfLobe, ProductLobeNormIsTheNormaliser) {
    for (float k1 : {0.1f, 0.3f, 1.f, 4.f, 9.f, 30.f})
        for (double theta = 0.0; theta < 3.1; theta += 0.05) {
            const VmfLobe a(kAxis, k1), b(rotate_away(kAxis, theta), 0.6f);
            const VmfProduct p = vmf_product(a, b);
            const double want = vmf_normalization(p.lobe.kappa);
            ASSERT_NEAR(p.lobe.norm, want, 3e-7 * want) << "k1 " << k1 << " theta " << theta;
        }
}

TEST(VmfLobe, NormalisedByQuadrature) {
    for (float kappa : {0.f, 1e-4f, 0.1f, 1.f, 10.f, 100.f, 1000.f, 32000.f}) {
        VmfLobe lobe(kAxis, kappa);
        double integral =
            integrate_sphere([&](const Vec3f& w) { return double(lobe.eval(w)); }, kAxis, peak_scale(kappa));
        EXPECT_NEAR(integral, 1.0, 1e-4) << "kappa " << kappa;
    }
}

TEST(VmfLobe, NormalisationMatchesTextbookFormWhereThatIsSafe) {
    // c(k) = k / (4 pi sinh k) and c~ = c e^k; compare where sinh does not overflow.
    for (double k : {1e-6, 1e-4, 1e-3, 0.05, 0.5, 3.0, 20.0, 80.0}) {
        double textbook = k / (4.0 * M_PI * std::sinh(k)) * std::exp(k);
        EXPECT_NEAR(vmf_normalization(k) / textbook, 1.0, 1e-12) << k;
    }
    EXPECT_DOUBLE_EQ(vmf_normalization(0.0), 1.0 / (4.0 * M_PI));
    EXPECT_NEAR(vmf_normalization(32000.0), 32000.0 / (2.0 * M_PI), 1e-9);
}

TEST(VmfLobe, EvalIsAccurateAtHighKappaNearTheAxis) {
    // kappa (1 - cos) must keep its relative precision: compare with a double-precision reference.
    const float kappa = 32000.f;
    VmfLobe lobe(kAxis, kappa);
    for (double theta : {1e-4, 1e-3, 3e-3, 1e-2, 3e-2}) {
        Vec3f w = rotate_away(kAxis, theta);
        double exact_theta = std::acos(
            std::clamp(dot(Vec3d(w), Vec3d(kAxis)) / (norm(Vec3d(w)) * norm(Vec3d(kAxis))), -1.0, 1.0));
        double one_minus = 2.0 * std::sin(exact_theta / 2) * std::sin(exact_theta / 2);
        double reference = vmf_normalization(kappa) * std::exp(-double(kappa) * one_minus);
        EXPECT_NEAR(lobe.eval(w) / reference, 1.0, 2e-4) << "theta " << theta;
    }
}

TEST(VmfLobe, NoNanOrInfAtTheEndsOfTheKappaRange) {
    for (float kappa : {0.f, 1e-30f, 1e-7f, 32000.f, 1e6f}) {
        VmfLobe lobe(kAxis, kappa);
        for (Vec3f w : {kAxis, -kAxis, Vec3f(1, 0, 0)}) {
            float v = lobe.eval(w);
            EXPECT_TRUE(std::isfinite(v) && v >= 0.f) << kappa;
        }
        for (Point2f u : {Point2f(0, 0), Point2f(OneMinusEpsilon, OneMinusEpsilon), Point2f(0.5f, 0.25f)}) {
            Vec3f w = lobe.sample(u);
            EXPECT_TRUE(all_finite(w)) << kappa;
            EXPECT_NEAR(norm(w), 1.f, 1e-5f) << kappa;
        }
        EXPECT_TRUE(std::isfinite(vmf_mean_cosine(kappa)));
    }
    // Equal antipodal lobes: the product is uniform, not NaN.
    VmfProduct p = vmf_product(VmfLobe(kAxis, 32000.f), VmfLobe(-kAxis, 32000.f));
    EXPECT_TRUE(std::isfinite(p.scale) && p.scale >= 0.0);
    EXPECT_TRUE(all_finite(p.lobe.mu) && std::isfinite(p.lobe.kappa));
    VmfProduct q = vmf_product(VmfLobe(kAxis, 5.f), VmfLobe(-kAxis, 5.f));
    EXPECT_EQ(q.lobe.kappa, 0.f);
    // Analytic value: c~(5)^2 / c~(0) * exp(-10).
    EXPECT_NEAR(q.scale / (vmf_normalization(5) * vmf_normalization(5) * 4 * M_PI * std::exp(-10.0)), 1.0,
                1e-6);
    VmfProduct u = vmf_product(VmfLobe(kAxis, 0.f), VmfLobe(-kAxis, 0.f));
    EXPECT_NEAR(u.scale * 4 * M_PI, 1.0, 1e-7);  // cached float c~ of the inputs
    EXPECT_EQ(u.lobe.kappa, 0.f);
}

TEST(VmfMeanCosine, MatchesClosedFormAndKnownValues) {
    for (double k : {1e-5, 1e-3, 0.01, 0.3, 1.0, 5.0, 30.0}) {
        double closed = 1.0 / std::tanh(k) - 1.0 / k;
        EXPECT_NEAR(vmf_mean_cosine(k), closed, 1e-9 * std::max(1.0, k)) << k;
    }
    // oracles.md §6: kappa(0.5) = 1.796756, kappa(0.9) = 9.9999996.
    EXPECT_NEAR(vmf_kappa_from_mean_cosine(0.5), 1.796756, 1e-6);
    EXPECT_NEAR(vmf_kappa_from_mean_cosine(0.9), 9.9999996, 1e-6);
    EXPECT_NEAR(vmf_mean_cosine(32000.0), 1.0 - 1.0 / 32000.0, 1e-12);
}

TEST(VmfMeanCosine, DerivativeMatchesFiniteDifference) {
    for (double k : {1e-3, 0.04, 0.06, 0.5, 2.0, 10.0, 200.0}) {
        double h = 1e-4 * k;
        double fd = (vmf_mean_cosine(k + h) - vmf_mean_cosine(k - h)) / (2 * h);
        EXPECT_NEAR(vmf_mean_cosine_derivative(k) / fd, 1.0, 1e-6) << k;
    }
}

TEST(VmfMeanCosine, BanerjeeErrorsMatchTheTableOfTheory) {
    // docs/theory.md §3.3: r, true kappa, relative error of (3.2).
    struct Row {
        double r, kappa, err;
    };
    for (Row row : {Row{0.1, 0.3018, 6.7e-4}, Row{0.3, 0.9532, 6.5e-3}, Row{0.5, 1.7968, 2.0e-2},
                    Row{0.7, 3.3035, 4.3e-2}, Row{0.9, 10.000, 3.7e-2}, Row{0.95, 20.000, 2.2e-2},
                    Row{0.99, 100.00, 4.9e-3}, Row{0.999, 1000.0, 5.0e-4}}) {
        double exact = vmf_kappa_from_mean_cosine(row.r);
        EXPECT_NEAR(exact, row.kappa, 1e-4 * row.kappa) << row.r;
        double err = std::abs(vmf_kappa_banerjee(row.r) - exact) / exact;
        EXPECT_NEAR(err, row.err, 0.06 * row.err + 1e-5) << row.r;
    }
}

TEST(VmfMeanCosine, InverseRoundTripsOverTheWholeRange) {
    for (double k = 1e-4; k <= 32000.0; k *= 1.37) {
        double back = vmf_kappa_from_mean_cosine(vmf_mean_cosine(k));
        EXPECT_NEAR(back / k, 1.0, 1e-6) << k;
    }
    EXPECT_EQ(vmf_kappa_from_mean_cosine(0.0), 0.0);
    EXPECT_EQ(vmf_kappa_from_mean_cosine(-0.3), 0.0);
    EXPECT_EQ(vmf_kappa_from_mean_cosine(1.0), double(kVmfMaxKappa));
    EXPECT_EQ(vmf_kappa_from_mean_cosine(std::nan("")), 0.0);
}

TEST(VmfProduct, ReferenceValuesOfTheory) {
    // kappa1 = 5, kappa2 = 20, axes 1 rad apart: s12 = 0.10189, kappa12 = 23.088 (docs/theory.md §14.3).
    VmfLobe a(kAxis, 5.f), b(rotate_away(kAxis, 1.0), 20.f);
    VmfProduct p = vmf_product(a, b);
    EXPECT_NEAR(p.scale, 0.10189, 5e-6);
    EXPECT_NEAR(p.lobe.kappa, 23.088, 5e-4);
}

TEST(VmfProduct, PointwiseIdentityAndIntegral) {
    struct Case {
        float k1, k2;
        double angle;
    };
    for (Case c : {Case{5, 20, 1.0}, Case{0.5f, 2, 2.5}, Case{100, 100, 3.0}, Case{1000, 30, 0.05},
                   Case{32000, 32000, 1e-3}, Case{0, 7, 1.2}, Case{3, 3, M_PI}}) {
        VmfLobe a(kAxis, c.k1), b(rotate_away(kAxis, c.angle), c.k2);
        VmfProduct p = vmf_product(a, b);
        for (double theta : {0.0, 1e-3, 0.01, 0.1, 0.5, 1.5, 3.0}) {
            for (double phi : {0.0, 2.0, 4.0}) {
                Vec3f w = rotate_away(p.lobe.kappa > 0 ? p.lobe.mu : kAxis, theta, phi);
                double lhs = eval_d(a, w) * eval_d(b, w), rhs = p.scale * eval_d(p.lobe, w);
                if (lhs < 1e-250 && rhs < 1e-250) continue;  // both underflow double
                // float storage of the product lobe: relative error ~1e-7 of the exponent.
                EXPECT_NEAR(std::log(lhs), std::log(rhs), 1e-5 + 1e-6 * std::abs(std::log(lhs)))
                    << c.k1 << " " << c.k2 << " " << c.angle << " theta " << theta;
            }
        }
        double integral = integrate_sphere([&](const Vec3f& w) { return eval_d(a, w) * eval_d(b, w); },
                                           p.lobe.kappa > 0 ? p.lobe.mu : kAxis, peak_scale(p.lobe.kappa));
        EXPECT_NEAR(integral / p.scale, 1.0, 1e-4) << c.k1 << " " << c.k2 << " " << c.angle;
    }
}

TEST(VmfConvolution, ExactValueMatchesQuadrature) {
    for (auto [k1, k2] : {std::pair{2.0, 2.0}, {5.0, 20.0}, {20.0, 50.0}, {50.0, 3.0}, {1000.0, 0.1}}) {
        for (double angle : {0.0, 0.3, 1.0, 2.5}) {
            VmfLobe a(kAxis, float(k1)), b(rotate_away(kAxis, angle), float(k2));
            double exact = vmf_convolution_exact(k1, k2, 1.0 - std::cos(angle));
            Vec3f center = normalize(a.mu * float(k1) + b.mu * float(k2));
            double quad = integrate_sphere([&](const Vec3f& w) { return double(a.eval(w)) * b.eval(w); },
                                           center, peak_scale(k1 + k2));
            EXPECT_NEAR(exact / quad, 1.0, 1e-4) << k1 << " " << k2 << " " << angle;
        }
    }
}

TEST(VmfConvolution, MeanCosineApproximationWithinFivePercentNearThePeak) {
    // Near the peak = every angle where the exact convolution is at least half its maximum.
    for (auto [k1, k2] : {std::pair{2.f, 2.f}, {5.f, 20.f}, {20.f, 50.f}, {50.f, 3.f}}) {
        VmfLobe approx(Vec3f(0, 0, 1), vmf_convolved_kappa(k1, k2));
        double peak = vmf_convolution_exact(k1, k2, 0.0);
        double worst = 0.0;
        for (double angle = 0.0; angle < M_PI; angle += 0.01) {
            double exact = vmf_convolution_exact(k1, k2, 1.0 - std::cos(angle));
            if (exact < 0.5 * peak) break;
            double value = approx.eval(rotate_away(Vec3f(0, 0, 1), angle));
            worst = std::max(worst, std::abs(value / exact - 1.0));
        }
        EXPECT_LT(worst, 0.05) << k1 << " " << k2;
    }
}

TEST(VmfConvolution, ConvolvedKappaMultipliesMeanCosines) {
    float k = vmf_convolved_kappa(5.f, 20.f);
    EXPECT_NEAR(vmf_mean_cosine(k), vmf_mean_cosine(5.0) * vmf_mean_cosine(20.0), 1e-6);
    EXPECT_EQ(vmf_convolved_kappa(0.f, 20.f), 0.f);
    EXPECT_NEAR(vmf_convolved_kappa(32000.f, 32000.f), 16000.f, 1.f);
}
