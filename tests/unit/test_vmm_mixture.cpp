// Mixture identities (docs/theory.md §3.6, §5.6): normalisation, lobe bookkeeping, products with their
// normaliser, convolution with zonal kernels (exact vs quadrature, A3 approximation vs exact),
// and the moment-matched merge.
#include <gtest/gtest.h>

#include "support/sphere_quadrature.h"
#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/vmm/vmm.h"

using namespace volguide;
using volguide::test::integrate_sphere;

namespace {
template <int N>
VmfMixture<N> random_mixture(int lobes, uint64_t seed, float kappa_min, float kappa_max) {
    VmfMixture<N> m;
    Sampler s(seed, 0, 0);
    for (int k = 0; k < lobes; ++k) {
        Vec3f mu = warp::square_to_uniform_sphere(s.next_2d());
        float kappa = kappa_min * std::pow(kappa_max / kappa_min, s.next_1d());
        m.add_lobe(0.2f + s.next_1d(), VmfLobe(mu, kappa));
    }
    m.normalize_weights();
    return m;
}
}  // namespace

TEST(VmmMixture, NormalisedByQuadrature) {
    auto m = random_mixture<8>(8, 3, 0.5f, 40.f);
    double integral =
        integrate_sphere([&](const Vec3f& w) { return double(m.pdf(w)); }, Vec3f(0, 0, 1), 0.05, 600, 24);
    EXPECT_NEAR(integral, 1.0, 1e-4);
}

TEST(VmmMixture, LobeBookkeeping) {
    VmfMixture<3> m;
    EXPECT_TRUE(m.add_lobe(0.5f, VmfLobe(Vec3f(1, 0, 0), 2.f)));
    EXPECT_TRUE(m.add_lobe(0.25f, VmfLobe(Vec3f(0, 1, 0), 3.f)));
    EXPECT_TRUE(m.add_lobe(0.25f, VmfLobe(Vec3f(0, 0, 1), 4.f)));
    EXPECT_FALSE(m.add_lobe(0.1f, VmfLobe()));
    EXPECT_EQ(m.size(), 3);
    m.remove_lobe(0);
    EXPECT_EQ(m.size(), 2);
    EXPECT_EQ(m.kappa[0], 3.f);
    EXPECT_EQ(m.kappa[1], 4.f);
    EXPECT_NEAR(m.normalize_weights(), 0.5, 1e-7);
    EXPECT_NEAR(m.weight[0], 0.5f, 1e-7f);
}

TEST(VmmMixture, SelectLobeReusesTheRandomNumber) {
    auto m = random_mixture<8>(5, 9, 1.f, 10.f);
    // Sweeping u over [0, 1) must visit the lobes in order, each over an interval of its weight,
    // with the rescaled number sweeping [0, 1) inside each interval.
    const int n = 100000;
    std::array<int, 8> hits{};
    float prev_u = -1.f;
    int prev_k = 0;
    for (int i = 0; i < n; ++i) {
        float u = (i + 0.5f) / n;
        int k = m.select_lobe(u);
        ASSERT_GE(u, 0.f);
        ASSERT_LT(u, 1.f);
        ASSERT_GE(k, prev_k);
        if (k == prev_k) {
            EXPECT_GE(u, prev_u - 1e-4f);
        }
        prev_k = k;
        prev_u = u;
        hits[k]++;
    }
    for (int k = 0; k < m.size(); ++k) EXPECT_NEAR(hits[k] / double(n), m.weight[k], 2e-5);
}

TEST(VmmMixture, ProductPointwiseAndNormaliser) {
    auto a = random_mixture<8>(8, 21, 1.f, 30.f);
    auto b = random_mixture<8>(8, 22, 1.f, 30.f);
    double z = 0.0;
    VmfMixture<64> p = product(a, b, &z);
    ASSERT_EQ(p.size(), 64);
    EXPECT_NEAR(p.weight_sum(), 1.0, 1e-5);
    Sampler s(5, 0, 0);
    for (int i = 0; i < 200; ++i) {
        Vec3f w = warp::square_to_uniform_sphere(s.next_2d());
        double lhs = double(a.eval(w)) * b.eval(w), rhs = z * p.eval(w);
        EXPECT_NEAR(lhs, rhs, 1e-5 * lhs + 1e-12);
    }
    double quad = integrate_sphere([&](const Vec3f& w) { return double(a.eval(w)) * b.eval(w); },
                                   Vec3f(0, 0, 1), 0.05, 600, 24);
    EXPECT_NEAR(z / quad, 1.0, 1e-4);
}

TEST(VmmMixture, ProductOfAntipodalMixturesIsFinite) {
    VmfMixture<2> a, b;
    a.add_lobe(0.5f, VmfLobe(Vec3f(0, 0, 1), 32000.f));
    a.add_lobe(0.5f, VmfLobe(Vec3f(1, 0, 0), 0.f));
    b.add_lobe(1.f, VmfLobe(Vec3f(0, 0, -1), 32000.f));
    double z = -1.0;
    auto p = product(a, b, &z);
    EXPECT_TRUE(std::isfinite(z) && z > 0.0);  // the uniform lobe keeps it non-zero
    for (int i = 0; i < p.size(); ++i) EXPECT_TRUE(std::isfinite(p.weight[i]) && std::isfinite(p.kappa[i]));
    EXPECT_TRUE(all_finite(p.sample({0.3f, 0.6f})));
    // Only antipodal peaks: Z underflows to 0 and the product is empty, never NaN.
    VmfMixture<1> c, d;
    c.add_lobe(1.f, VmfLobe(Vec3f(0, 0, 1), 32000.f));
    d.add_lobe(1.f, VmfLobe(Vec3f(0, 0, -1), 32000.f));
    auto e = product(c, d, &z);
    EXPECT_EQ(z, 0.0);
    EXPECT_EQ(e.size(), 0);
}

TEST(VmmMixture, ConvolutionWithZonalKernelExactMatchesQuadrature) {
    auto m = random_mixture<4>(4, 31, 2.f, 50.f);
    ZonalMixture<3> kernel;
    kernel.count = 3;
    kernel.weight = {0.3f, 0.5f, 0.2f};
    kernel.kappa = {20.f, 3.f, 0.5f};
    kernel.sign = {1.f, 1.f, -1.f};
    Sampler s(2, 0, 0);
    for (int i = 0; i < 6; ++i) {
        Vec3f w = warp::square_to_uniform_sphere(s.next_2d());
        auto f = kernel.oriented(w);
        double quad = integrate_sphere([&](const Vec3f& x) { return double(f.eval(x)) * m.eval(x); },
                                       Vec3f(0, 0, 1), 0.05, 600, 24);
        double z = 0.0;
        product(f, m, &z);
        double exact = convolve_exact(m, kernel, w);
        EXPECT_NEAR(exact / quad, 1.0, 1e-4);
        EXPECT_NEAR(z / exact, 1.0, 1e-6);  // the product normaliser is the same quantity
    }
}

TEST(VmmMixture, ConvolutionApproximationNearThePeak) {
    VmfMixture<1> m;
    const Vec3f mu = normalize(Vec3f(0.2f, 0.3f, 0.9f));
    m.add_lobe(1.f, VmfLobe(mu, 20.f));
    ZonalMixture<2> kernel;
    kernel.count = 2;
    kernel.weight = {0.6f, 0.4f};
    kernel.kappa = {50.f, 5.f};
    kernel.sign = {1.f, 1.f};
    auto approx = convolve(m, kernel);
    ASSERT_EQ(approx.size(), 2);
    double peak = convolve_exact(m, kernel, mu);
    EXPECT_NEAR(approx.eval(mu) / peak, 1.0, 0.05);
    // A flipped kernel moves the peak to -mu.
    kernel.sign = {-1.f, -1.f};
    auto flipped = convolve(m, kernel);
    EXPECT_NEAR(flipped.eval(-mu) / convolve_exact(m, kernel, -mu), 1.0, 0.05);
    EXPECT_GT(flipped.eval(-mu), 100.f * flipped.eval(mu));
}

TEST(VmmMixture, SingleKernelConvolutionScalesTheMeanVector) {
    auto m = random_mixture<8>(6, 41, 0.5f, 100.f);
    auto c = convolve(m, 10.f);
    Vec3f before = m.mean_vector(), after = c.mean_vector();
    float a3 = float(vmf_mean_cosine(10.0));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(after[i], a3 * before[i], 1e-5f);
}

TEST(VmmMixture, MergePreservesWeightAndMeanVector) {
    VmfMixture<4> m;
    m.add_lobe(0.3f, VmfLobe(normalize(Vec3f(1, 0.1f, 0)), 15.f));
    m.add_lobe(0.2f, VmfLobe(normalize(Vec3f(1, -0.1f, 0.05f)), 40.f));
    m.add_lobe(0.5f, VmfLobe(Vec3f(0, 0, 1), 2.f));
    Vec3f before = m.mean_vector();
    m.merge(1, 0);
    ASSERT_EQ(m.size(), 2);
    EXPECT_NEAR(m.weight[0], 0.5f, 1e-6f);
    Vec3f after = m.mean_vector();
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(after[i], before[i], 1e-5f);
    EXPECT_EQ(m.kappa[1], 2.f);
    // Merging two identical lobes returns the lobe itself.
    WeightedLobe same =
        merge_lobes({0.4f, VmfLobe(Vec3f(0, 1, 0), 7.f)}, {0.1f, VmfLobe(Vec3f(0, 1, 0), 7.f)});
    EXPECT_NEAR(same.weight, 0.5f, 1e-7f);
    EXPECT_NEAR(same.lobe.kappa, 7.f, 1e-4f);
    // Opposite lobes cancel to a uniform lobe.
    WeightedLobe opposite =
        merge_lobes({0.5f, VmfLobe(Vec3f(0, 1, 0), 7.f)}, {0.5f, VmfLobe(Vec3f(0, -1, 0), 7.f)});
    EXPECT_EQ(opposite.lobe.kappa, 0.f);
}
