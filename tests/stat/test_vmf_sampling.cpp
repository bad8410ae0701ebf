// vMF lobe sampling (docs/theory.md §3.2, §14.1): chi-square against the lobe's own pdf, and the
// sample mean cosine against A3(kappa) over the whole kappa range.
#include <gtest/gtest.h>

#include "support/chi2.h"
#include "volguide/vmm/vmf.h"

using namespace volguide;
using namespace volguide::test;

namespace {
constexpr float kKappas[] = {0.f, 0.5f, 5.f, 50.f};
}

TEST(VmfSampling, ChiSquare) {
    for (float kappa : kKappas) {
        VmfLobe lobe(normalize(Vec3f(0.4f, 0.2f, -0.6f)), kappa);
        ChiSquareOptions opt;
        opt.test_count = int(std::size(kKappas));
        opt.seed = 7 + uint64_t(kappa * 10);
        auto r = chi2_test_sphere([&](Sampler& s) { return ChiSquareSample{lobe.sample(s.next_2d())}; },
                                  [&](const Vec3f& d) { return double(lobe.pdf(d)); }, opt,
                                  [&](const Vec3f& d) { return Color3(lobe.eval(d)); });
        EXPECT_TRUE(r.passed) << "kappa " << kappa << "\n" << r.report;
        EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4);
    }
}

TEST(VmfSampling, WrongKappaIsDetected) {
    // The test must be able to fail: samples with kappa 5, pdf claims kappa 5.5.
    VmfLobe lobe(Vec3f(0, 0, 1), 5.f), other(Vec3f(0, 0, 1), 5.5f);
    ChiSquareOptions opt;
    opt.sample_count = 200000;
    auto r = chi2_test_sphere([&](Sampler& s) { return ChiSquareSample{lobe.sample(s.next_2d())}; },
                              [&](const Vec3f& d) { return double(other.pdf(d)); }, opt);
    EXPECT_FALSE(r.passed);
}

TEST(VmfSampling, MeanCosineIsA3) {
    const Vec3f mu = normalize(Vec3f(-0.2f, 0.9f, 0.1f));
    const int n = 200000;
    for (float kappa : {0.f, 0.01f, 1.f, 10.f, 100.f, 1000.f, 32000.f}) {
        VmfLobe lobe(mu, kappa);
        double sum = 0.0, sum_one_minus = 0.0;
        for (int i = 0; i < n; ++i) {
            Sampler s(11, 0, uint64_t(i));
            Vec3f w = lobe.sample(s.next_2d());
            ASSERT_TRUE(all_finite(w));
            sum += dot(Vec3d(w), Vec3d(mu));
            sum_one_minus += one_minus_cos(w, mu);
        }
        double a3 = vmf_mean_cosine(kappa);
        // Var(cos) = E[cos^2] - A3^2 with E[cos^2] = 1 - 2 A3 / kappa (1/3 at kappa = 0).
        double e2 = kappa > 0 ? 1.0 - 2.0 * a3 / kappa : 1.0 / 3.0;
        double sigma = std::sqrt(std::max(e2 - a3 * a3, 0.0) / n);
        EXPECT_NEAR(sum / n, a3, 4.5 * sigma + 1e-7) << "kappa " << kappa;
        // The tail 1 - cos must keep its relative precision at high kappa: E[1 - cos] = 1 - A3.
        EXPECT_NEAR(sum_one_minus / n / (1.0 - a3), 1.0, 4.5 * sigma / (1.0 - a3) + 1e-4)
            << "kappa " << kappa;
    }
}
