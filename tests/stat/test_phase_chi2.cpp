// Chi-square tests (oracles.md §8) of the HG and isotropic samplers against their own pdf.
// Peaked lobes are rotated onto +z and the (cos theta, phi) grid is zoomed onto the cap
// cos theta >= 1 - delta so that the peak is resolved; the rest of the sphere is the rest bin.
#include <gtest/gtest.h>

#include "support/chi2.h"
#include "volguide/media/phase_hg.h"
#include "volguide/media/phase_isotropic.h"

using namespace volguide;
using namespace volguide::test;

namespace {

constexpr float kGs[] = {-0.99f, -0.9f, -0.5f, 0.f, 0.3f, 0.9f, 0.99f};
constexpr int kPhaseTests = int(std::size(kGs)) * 2 + 1;

// Cap half-width in 1 - cos theta holding the bulk of the lobe: a few times (1 - g)^2 / (2 g).
double zoom_delta(float g) {
    const double a = std::abs(g);
    if (a < 0.8) return 2.0;
    return std::min(2.0, 40.0 * (1 - a) * (1 - a) / (2 * a));
}

ChiSquareResult run(const PhaseFunction& phase, const Vec3f& wi, double min_cos, uint64_t seed) {
    ChiSquareOptions opt;
    opt.test_count = kPhaseTests;
    opt.seed = seed;
    opt.min_cos_theta = min_cos;
    return chi2_test_sphere([&](Sampler& s) { return ChiSquareSample{phase.sample(wi, s.next_2d()).wo}; },
                            [&](const Vec3f& d) { return double(phase.pdf(wi, d)); }, opt,
                            [&](const Vec3f& d) { return Color3(phase.eval(wi, d)); });
}

}  // namespace

TEST(PhaseChi2, HenyeyGreensteinZoomedOnThePeak) {
    for (float g : kGs) {
        HGPhase hg(g);
        // Put the peak on +z: forward lobes peak at -wi, backward ones at wi.
        const Vec3f wi = g >= 0.f ? Vec3f(0, 0, -1) : Vec3f(0, 0, 1);
        auto r = run(hg, wi, 1.0 - zoom_delta(g), 100 + uint64_t(100 * (g + 1)));
        EXPECT_TRUE(r.passed) << "g " << g << "\n" << r.report;
        EXPECT_GT(r.dof, 500) << "g " << g << ": the zoomed grid must resolve the lobe\n" << r.report;
        if (getenv("VOLGUIDE_VERBOSE")) std::cout << "g " << g << ": " << r.report << "\n";
    }
}

TEST(PhaseChi2, HenyeyGreensteinWholeSphereObliqueWi) {
    for (float g : kGs) {
        HGPhase hg(g);
        auto r = run(hg, normalize(Vec3f(0.3f, -0.6f, 0.5f)), -1.0, 200 + uint64_t(100 * (g + 1)));
        EXPECT_TRUE(r.passed) << "g " << g << "\n" << r.report;
        if (std::abs(g) < 0.95f) {
            EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3) << g;
        }
    }
}

TEST(PhaseChi2, Isotropic) {
    IsotropicPhase iso;
    auto r = run(iso, Vec3f(0, 0, 1), -1.0, 7);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4);
}

TEST(PhaseChi2, WrongGIsDetected) {
    // The test must be able to fail: samples with g = 0.9, pdf of g = 0.88.
    HGPhase a(0.9f), b(0.88f);
    const Vec3f wi(0, 0, -1);
    ChiSquareOptions opt;
    opt.sample_count = 200000;
    opt.min_cos_theta = 1.0 - zoom_delta(0.9f);
    auto r = chi2_test_sphere([&](Sampler& s) { return ChiSquareSample{a.sample(wi, s.next_2d()).wo}; },
                              [&](const Vec3f& d) { return double(b.pdf(wi, d)); }, opt);
    EXPECT_FALSE(r.passed);
}
