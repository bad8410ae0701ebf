// Mixture sampling (docs/theory.md §3.6, §14.6): chi-square of an 8-lobe mixture and of the product of
// two 8-lobe mixtures (64 lobes) against their own pdfs.
#include <gtest/gtest.h>

#include "support/chi2.h"
#include "volguide/core/warp.h"
#include "volguide/vmm/phase_vmm.h"
#include "volguide/vmm/vmm.h"

using namespace volguide;
using namespace volguide::test;

namespace {
VmfMixture<8> random_mixture(uint64_t seed, float kappa_min, float kappa_max) {
    VmfMixture<8> m;
    Sampler s(seed, 0, 0);
    for (int k = 0; k < 8; ++k) {
        Vec3f mu = warp::square_to_uniform_sphere(s.next_2d());
        m.add_lobe(0.2f + s.next_1d(), VmfLobe(mu, kappa_min * std::pow(kappa_max / kappa_min, s.next_1d())));
    }
    m.normalize_weights();
    return m;
}

template <int N>
ChiSquareResult check(const VmfMixture<N>& m, int test_count, uint64_t seed) {
    ChiSquareOptions opt;
    opt.test_count = test_count;
    opt.seed = seed;
    return chi2_test_sphere([&](Sampler& s) { return ChiSquareSample{m.sample(s.next_2d())}; },
                            [&](const Vec3f& d) { return double(m.pdf(d)); }, opt,
                            [&](const Vec3f& d) { return Color3(m.eval(d)); });
}
}  // namespace

TEST(VmmSampling, EightLobeMixtureChiSquare) {
    auto m = random_mixture(1, 0.2f, 30.f);
    auto r = check(m, 4, 17);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4);
}

TEST(VmmSampling, ProductOfTwoEightLobeMixturesChiSquare) {
    auto a = random_mixture(2, 0.5f, 10.f), b = random_mixture(3, 0.5f, 10.f);
    double z = 0.0;
    VmfMixture<64> p = product(a, b, &z);
    ASSERT_GT(z, 0.0);
    auto r = check(p, 4, 18);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4);
}

TEST(VmmSampling, RadianceTimesPhaseProductChiSquare) {
    // The guided-direction product (docs/theory.md §8): radiance VMM x HG(g = 0.7) VMM about a travel
    // direction, 8 x 3 lobes.
    auto radiance = random_mixture(5, 0.5f, 20.f);
    Vmm big;
    for (int k = 0; k < radiance.size(); ++k) big.add_lobe(radiance.weight[k], radiance.lobe(k));
    PhaseVmm phase = hg_phase_vmm(0.7f);
    double z = 0.0;
    auto p = product(big, phase.oriented(normalize(Vec3f(0.3f, -0.2f, 0.9f))), &z);
    ASSERT_EQ(p.size(), 8 * phase.count);
    ASSERT_GT(z, 0.0);
    auto r = check(p, 4, 19);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4);
}

TEST(VmmSampling, WrongLobeChoiceIsDetected) {
    // Sampling with a perturbed weight must fail against the true pdf.
    auto m = random_mixture(4, 1.f, 20.f);
    auto biased = m;
    biased.weight[0] *= 1.6f;
    biased.normalize_weights();
    ChiSquareOptions opt;
    opt.sample_count = 300000;
    auto r = chi2_test_sphere([&](Sampler& s) { return ChiSquareSample{biased.sample(s.next_2d())}; },
                              [&](const Vec3f& d) { return double(m.pdf(d)); }, opt);
    EXPECT_FALSE(r.passed) << r.report;
}
