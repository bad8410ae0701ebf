// Microfacet distribution identities: D is normalised over projected area, the visible normal
// density integrates to one (exactly for GGX, within Mitsuba's Smith approximation for
// Beckmann), sample() returns its pdf(), and erfinv inverts erf.
#include <gtest/gtest.h>

#include <cmath>

#include "support/chi2.h"
#include "volguide/render/bsdfs/microfacet.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// Integral of f over the sphere by the chi-square harness's adaptive quadrature.
double integrate_microfacet(const ChiSquarePdfFn& f) {
    ChiSquareOptions opt;
    opt.sample_count = 1;      // only the quadrature is used
    opt.abs_tolerance = 1e-8;  // absolute quadrature tolerance (divided by sample_count)
    return chi2_test_sphere(
               [](Sampler&) {
                   return ChiSquareSample{Vec3f(0, 0, 1), Color3(1.f), false};
               },
               f, opt)
        .pdf_integral;
}

}  // namespace

TEST(Microfacet, ProjectedAreaNormalisation) {
    for (auto type : {MicrofacetType::Beckmann, MicrofacetType::GGX})
        for (float a : {0.05f, 0.3f, 0.9f}) {
            MicrofacetDistribution d(type, a, a * 0.5f);
            double i = integrate_microfacet([&](const Vec3f& m) { return m.z > 0 ? double(d.eval(m)) * m.z : 0.0; });
            EXPECT_NEAR(i, 1.0, 2e-3) << int(type) << " alpha " << a;
        }
}

TEST(Microfacet, VisibleNormalDensityIntegratesToOne) {
    const Vec3f wi = normalize(Vec3f(0.6f, 0.2f, 0.5f));
    for (auto type : {MicrofacetType::Beckmann, MicrofacetType::GGX})
        for (float a : {0.1f, 0.5f}) {
            MicrofacetDistribution d(type, a, a);
            double i = integrate_microfacet([&](const Vec3f& m) { return m.z > 0 ? double(d.pdf(wi, m)) : 0.0; });
            // Beckmann uses Mitsuba's rational Smith approximation (< 0.35% error).
            EXPECT_NEAR(i, 1.0, type == MicrofacetType::GGX ? 2e-3 : 5e-3) << int(type) << " alpha " << a;
        }
}

TEST(Microfacet, SampleReturnsItsPdf) {
    const Vec3f wi = normalize(Vec3f(-0.3f, 0.5f, 0.7f));
    for (auto type : {MicrofacetType::Beckmann, MicrofacetType::GGX})
        for (bool visible : {true, false}) {
            MicrofacetDistribution d(type, 0.2f, 0.4f, visible);
            for (int i = 0; i < 50; ++i) {
                Sampler s(5, 0, uint64_t(i));
                auto [m, pdf] = d.sample(wi, s.next_2d());
                EXPECT_NEAR(norm(m), 1.f, 1e-5f);
                EXPECT_GT(m.z, 0.f);
                EXPECT_NEAR(pdf, d.pdf(wi, m), 2e-3f * pdf + 1e-6f);
            }
        }
}

TEST(Microfacet, SmithMasking) {
    MicrofacetDistribution ggx(MicrofacetType::GGX, 0.5f, 0.5f);
    const Vec3f n(0, 0, 1);
    EXPECT_EQ(ggx.smith_g1(n, n), 1.f);
    // GGX closed form 2 / (1 + sqrt(1 + alpha^2 tan^2)).
    const Vec3f v = normalize(Vec3f(0.8f, 0.f, 0.6f));
    EXPECT_NEAR(ggx.smith_g1(v, n), 2.f / (1.f + std::sqrt(1.f + 0.25f * (0.64f / 0.36f))), 1e-6f);
    // Back-facing microfacet: masked.
    EXPECT_EQ(ggx.smith_g1(v, normalize(Vec3f(-1.f, 0.f, 0.1f))), 0.f);
    // Beckmann approximation against the exact 2 / (1 + erf(a) + exp(-a^2) / (a sqrt(pi))).
    MicrofacetDistribution beck(MicrofacetType::Beckmann, 0.5f, 0.5f);
    for (float c : {0.3f, 0.6f, 0.9f}) {
        Vec3f w(std::sqrt(1 - c * c), 0.f, c);
        double a = 1.0 / (0.5 * std::sqrt(1 - c * c) / c);
        double exact = 2.0 / (1.0 + std::erf(a) + std::exp(-a * a) / (a * std::sqrt(M_PI)));
        EXPECT_NEAR(beck.smith_g1(w, n), exact, 0.0035 * exact);
    }
}

TEST(Microfacet, ErfInverse) {
    for (float x : {-0.999f, -0.9f, -0.5f, -0.1f, 0.f, 0.2f, 0.7f, 0.99f, 0.9999f})
        EXPECT_NEAR(std::erf(erfinv(x)), x, 2e-6f) << x;
}
