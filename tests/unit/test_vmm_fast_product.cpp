// The single-precision mixture x lobe product (vmm/vmm_fast_product.h) against the double
// reference product_into (vmm.h), and the surface guide built from it (guiding/surface_guide.h):
// its value is proportional to V(w) times the cosine lobe and integrates to one.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "support/sphere_quadrature.h"
#include "volguide/guiding/surface_guide.h"
#include "volguide/vmm/phase_vmm.h"
#include "volguide/vmm/vmm_fast_product.h"

using namespace volguide;
using namespace volguide::test;

namespace {

Vec3f random_direction(std::mt19937& rng) {
    std::normal_distribution<float> n;
    Vec3f v;
    do v = Vec3f(n(rng), n(rng), n(rng));
    while (squared_norm(v) < 1e-6f);
    return normalize(v);
}

}  // namespace

TEST(VmmFastProduct, NormalizationMatchesTheDoubleOne) {
    for (float k : {0.f, 1e-5f, 5e-4f, 1e-3f, 0.1f, 0.2499f, 0.25f, 1.f, 8.99f, 9.f, 50.f, 32000.f})
        EXPECT_NEAR(vmf_normalization_fast(k), vmf_normalization(k), 2e-6 * vmf_normalization(k)) << k;
}

TEST(VmmFastProduct, MatchesTheDoublePrecisionProduct) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (int trial = 0; trial < 2000; ++trial) {
        Vmm a;
        const int lobes = 1 + int(u(rng) * 8.f);
        for (int k = 0; k < lobes; ++k) {
            // kappa log-uniform over [1e-4, 32000], plus exact zeros.
            const float kappa = trial % 50 == 0 && k == 0 ? 0.f : std::exp(std::log(1e-4f) + u(rng) * std::log(3.2e8f));
            a.add_lobe(0.05f + u(rng), VmfLobe(random_direction(rng), kappa));
        }
        a.normalize_weights();
        const float kb = trial % 3 == 0 ? cosine_lobe_kappa() : std::exp(std::log(1e-3f) + u(rng) * std::log(1e6f));
        const VmfLobe b(random_direction(rng), kb);
        VmfMixture<1> bm;
        bm.add_lobe(1.f, b);
        Vmm ref, fast;
        const double z_ref = product_into(a, bm, ref);
        const double z_fast = product_with_lobe_fast(a, b, fast);
        if (ref.count == 0) {
            // The double product underflowed (every lobe's exp(kappa_12 - kappa_a - kappa_b) below
            // 1e-308); the fast one scales by the largest lobe and keeps a normalised shape.
            EXPECT_EQ(z_ref, 0.0);
            if (fast.count > 0) {
                EXPECT_NEAR(fast.weight_sum(), 1.0, 1e-5);
            }
            continue;
        }
        ASSERT_EQ(ref.count, fast.count);
        EXPECT_NEAR(z_fast, z_ref, 1e-4 * z_ref) << trial;
        for (int k = 0; k < ref.count; ++k) {
            EXPECT_NEAR(fast.weight[k], ref.weight[k], 1e-4 * ref.weight[k] + 1e-6) << trial << " lobe " << k;
            EXPECT_NEAR(fast.kappa[k], ref.kappa[k], 1e-4 * ref.kappa[k] + 1e-4) << trial;
            EXPECT_NEAR(fast.norm[k], ref.norm[k], 1e-4 * ref.norm[k]) << trial;
            if (ref.kappa[k] > 0.f) {
                const Vec3f dr(ref.mu_x[k], ref.mu_y[k], ref.mu_z[k]), df(fast.mu_x[k], fast.mu_y[k], fast.mu_z[k]);
                EXPECT_LT(norm(dr - df), 1e-5f) << trial;
            }
        }
    }
}

TEST(VmmFastProduct, EmptyOrMasslessInputGivesNoProduct) {
    Vmm a, out;
    EXPECT_EQ(product_with_lobe_fast(a, VmfLobe(Vec3f(0, 0, 1), 3.f), out), 0.0);
    EXPECT_EQ(out.count, 0);
    a.add_lobe(0.f, VmfLobe(Vec3f(0, 0, 1), 3.f));  // zero weight
    EXPECT_EQ(product_with_lobe_fast(a, VmfLobe(Vec3f(0, 0, 1), 3.f), out), 0.0);
    EXPECT_EQ(out.count, 0);
}

TEST(SurfaceGuide, CosineLobeHasTheClampedCosinesMeanCosine) {
    EXPECT_NEAR(vmf_mean_cosine(cosine_lobe_kappa()), 2.0 / 3.0, 1e-6);
    EXPECT_NEAR(cosine_lobe_kappa(), 2.96, 0.01);
}

TEST(SurfaceGuide, CosineProductIsTheNormalisedProduct) {
    Vmm v;
    v.add_lobe(0.5f, VmfLobe(normalize(Vec3f(0.2f, 0.9f, 0.1f)), 12.f));
    v.add_lobe(0.3f, VmfLobe(normalize(Vec3f(-0.5f, -0.5f, 0.7f)), 3.f));
    v.add_lobe(0.2f, VmfLobe(normalize(Vec3f(0.1f, -0.2f, -0.97f)), 40.f));  // mostly below the surface
    const Vec3f n = normalize(Vec3f(0.1f, 0.3f, 0.95f));
    Vmm g;
    ASSERT_TRUE(cosine_product(v, n, g));
    const VmfLobe cosine(n, cosine_lobe_kappa());
    const double z = integrate_sphere([&](const Vec3f& w) { return double(v.eval(w)) * cosine.eval(w); }, n, 0.05);
    EXPECT_NEAR(integrate_sphere([&](const Vec3f& w) { return double(g.eval(w)); }, n, 0.05), 1.0, 1e-4);
    for (const Vec3f& w : {n, normalize(Vec3f(0.2f, 0.9f, 0.1f)), normalize(Vec3f(1.f, 0.f, 0.1f)), -n}) {
        const double expected = double(v.eval(w)) * cosine.eval(w) / z;
        EXPECT_NEAR(g.eval(w), expected, 1e-4 * expected + 1e-9);
    }
    // The lobe below the surface keeps little of its mass: e^{-2 kappa_cos} at the antipode.
    EXPECT_LT(g.weight[2], 0.01f);
}
