// Self-test of the shared chi-square harness (tests/support/chi2.h): correct samplers pass,
// wrong pdfs, zero-pdf hits, wrong weights and wrong discrete probabilities fail.
#include <gtest/gtest.h>

#include "support/chi2.h"
#include "volguide/core/warp.h"

using namespace volguide;
using namespace volguide::test;

namespace {

ChiSquareSample cosine_sample(Sampler& s) {
    Vec3f d = warp::square_to_cosine_hemisphere(s.next_2d());
    return {d, Color3(1.f)};
}

}  // namespace

TEST(Chi2Distribution, KnownQuantiles) {
    EXPECT_NEAR(chi2_survival(3.841459, 1), 0.05, 1e-6);
    EXPECT_NEAR(chi2_survival(18.307038, 10), 0.05, 1e-6);
    EXPECT_NEAR(chi2_survival(6.634897, 1), 0.01, 1e-6);
    EXPECT_NEAR(chi2_survival(1118.948, 1000), 0.005, 1e-4);
    EXPECT_NEAR(gamma_q(1.0, 2.0), std::exp(-2.0), 1e-12);
}

TEST(Chi2Harness, CosineHemispherePasses) {
    ChiSquareOptions opt;
    auto r = chi2_test_sphere(
        cosine_sample, [](const Vec3f& d) { return double(warp::square_to_cosine_hemisphere_pdf(d)); }, opt,
        [](const Vec3f& d) { return Color3(std::max(d.z, 0.f) * InvPi); });
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-5);
    EXPECT_EQ(r.weight_mismatches, 0u);
}

TEST(Chi2Harness, WrongPdfFails) {
    ChiSquareOptions opt;
    opt.sample_count = 200000;
    auto r = chi2_test_sphere(
        cosine_sample, [](const Vec3f& d) { return double(warp::square_to_uniform_hemisphere_pdf(d)); }, opt);
    EXPECT_FALSE(r.passed) << r.report;
    // A subtle error: pdf proportional to cos^1.1 instead of cos.
    auto r2 = chi2_test_sphere(
        cosine_sample, [](const Vec3f& d) { return d.z > 0 ? std::pow(d.z, 1.1) * 2.1 / (2 * M_PI) : 0.0; });
    EXPECT_FALSE(r2.passed) << r2.report;
}

TEST(Chi2Harness, ZeroPdfCellFails) {
    ChiSquareOptions opt;
    opt.sample_count = 100000;
    // Samples the whole sphere; the pdf claims the upper hemisphere only (and integrates to 1).
    auto r = chi2_test_sphere(
        [](Sampler& s) { return ChiSquareSample{warp::square_to_uniform_sphere(s.next_2d())}; },
        [](const Vec3f& d) { return d.z > 0 ? double(InvTwoPi) : 0.0; }, opt);
    EXPECT_FALSE(r.passed);
    EXPECT_GT(r.zero_pdf_hits, 0u) << r.report;
}

TEST(Chi2Harness, WrongWeightFails) {
    ChiSquareOptions opt;
    opt.sample_count = 100000;
    auto r = chi2_test_sphere(
        cosine_sample, [](const Vec3f& d) { return double(warp::square_to_cosine_hemisphere_pdf(d)); }, opt,
        [](const Vec3f& d) { return Color3(0.9f * std::max(d.z, 0.f) * InvPi); });
    EXPECT_FALSE(r.passed);
    EXPECT_GT(r.weight_mismatches, 0u) << r.report;
}

TEST(Chi2Harness, DeltaMassInRestBin) {
    auto sampler_with_delta = [](float p_delta) {
        return [p_delta](Sampler& s) {
            if (s.next_1d() < p_delta) return ChiSquareSample{Vec3f(0, 0, 1), Color3(1.f), true, true};
            return cosine_sample(s);
        };
    };
    auto pdf = [](const Vec3f& d) { return 0.7 * warp::square_to_cosine_hemisphere_pdf(d); };
    auto ok = chi2_test_sphere(sampler_with_delta(0.3f), pdf);
    EXPECT_TRUE(ok.passed) << ok.report;
    EXPECT_NEAR(double(ok.rest_observed), 3e5, 5 * std::sqrt(3e5 * 0.7));
    auto bad = chi2_test_sphere(sampler_with_delta(0.31f), pdf);
    EXPECT_FALSE(bad.passed) << bad.report;
}

TEST(Chi2Harness, PlaneAndDiscrete) {
    ChiSquareOptions opt;
    opt.sample_count = 200000;
    opt.rows = opt.cols = 20;
    // Density 2x on [0,1]: sampled by inversion (x = sqrt(u)).
    auto sample = [](Sampler& s) {
        Vec2f u = s.next_2d();
        return ChiSquareSample{Vec3f(std::sqrt(u.x), 2.f * u.y, 0.f)};
    };
    auto good = chi2_test_plane(
        sample, [](const Vec3f& p) { return double(p.x); }, Rect2{0, 0, 1, 2}, opt);
    EXPECT_TRUE(good.passed) << good.report;
    auto bad = chi2_test_plane(
        sample, [](const Vec3f& p) { return 0.5; }, Rect2{0, 0, 1, 2}, opt);
    EXPECT_FALSE(bad.passed) << bad.report;

    auto d1 = chi2_test_discrete({2480, 7520}, {0.25, 0.75});
    EXPECT_TRUE(d1.passed) << d1.report;
    auto d2 = chi2_test_discrete({2800, 7200}, {0.25, 0.75});
    EXPECT_FALSE(d2.passed) << d2.report;
}

TEST(Chi2Harness, NonFiniteSamplesFail) {
    ChiSquareOptions opt;
    opt.sample_count = 100000;
    auto r = chi2_test_sphere(
        [](Sampler& s) {
            ChiSquareSample c = cosine_sample(s);
            if (s.next_1d() < 1e-3f) c.d = Vec3f(NAN, 0.f, 1.f);
            return c;
        },
        [](const Vec3f& d) { return double(warp::square_to_cosine_hemisphere_pdf(d)); }, opt);
    EXPECT_FALSE(r.passed);
    EXPECT_NE(r.report.find("non-finite"), std::string::npos) << r.report;
}

TEST(Chi2Harness, NarrowLobeAtThePole) {
    // pdf = (n + 1) / (2 pi) cos^n theta, about 0.03 rad wide: the quadrature must resolve it.
    const double n = 2000;
    auto sample = [n](Sampler& s) {
        Vec2f u = s.next_2d();
        float z = float(std::pow(double(u.x), 1.0 / (n + 1))), r = safe_sqrt(1.f - z * z);
        float phi = 2.f * Pi * u.y;
        return ChiSquareSample{Vec3f(r * std::cos(phi), r * std::sin(phi), z)};
    };
    auto pdf = [n](const Vec3f& d) {
        return d.z > 0 ? (n + 1) / (2 * M_PI) * std::pow(double(d.z), n) : 0.0;
    };
    auto r = chi2_test_sphere(sample, pdf);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4);
    // On the full sphere the whole lobe falls into the top row of cells, so a 10% error in its
    // width goes unnoticed; zooming the grid onto the cap around +z resolves it.
    ChiSquareOptions zoom;
    zoom.min_cos_theta = std::cos(0.15);
    auto wrong_pdf = [n](const Vec3f& d) {
        return d.z > 0 ? (1.1 * n + 1) / (2 * M_PI) * std::pow(double(d.z), 1.1 * n) : 0.0;
    };
    auto r_zoom = chi2_test_sphere(sample, pdf, zoom);
    EXPECT_TRUE(r_zoom.passed) << r_zoom.report;
    auto wrong = chi2_test_sphere(sample, wrong_pdf, zoom);
    EXPECT_FALSE(wrong.passed) << wrong.report;
}
