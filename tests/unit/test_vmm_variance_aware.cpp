// The variance-aware target on a fitted mixture (vmm/vmm_variance_aware.h, docs/theory.md §23):
//  - on an exact second-moment field sqrt(E[L^2]) = sum_k s_k v_k, the lobe weights become s / sum(s):
//    a broad and a narrow lobe, whose cross term 2 s_1 s_2 v_1 v_2 sits under the narrow lobe and
//    is as large as the broad lobe's own square there (the radiance fit's responsibilities would
//    credit it to the broad lobe: 0.43 instead of 1/3);
//  - on noisy one-sample estimates L^ / p of a known mean: noise-free estimates give the radiance
//    weights back, and one lobe's light estimated 1/q-or-0 (q = 1/4) doubles that lobe's share;
//  - no second moment: the mixture is left as it is.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "volguide/core/math.h"
#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/vmm/vmm_variance_aware.h"

using namespace volguide;

namespace {

// A broad lobe on +z and a narrow one on -z with the given weights.
Vmm variance_aware_two_lobes(float w_broad, float w_narrow) {
    Vmm m;
    m.add_lobe(w_broad, VmfLobe(Vec3f(0.f, 0.f, 1.f), 0.8f));
    m.add_lobe(w_narrow, VmfLobe(Vec3f(0.f, 0.f, -1.f), 50.f));
    return m;
}

// Directions of an equal-area grid (n_t cells in cos(theta), n_phi in phi), each of solid angle 4 pi / n.
std::vector<Vec3f> variance_aware_grid(int n_t, int n_phi) {
    std::vector<Vec3f> out;
    for (int i = 0; i < n_t; ++i)
        for (int j = 0; j < n_phi; ++j)
            out.push_back(warp::square_to_uniform_sphere(Point2f((float(i) + 0.5f) / float(n_t),
                                                                  (float(j) + 0.5f) / float(n_phi))));
    return out;
}

}  // namespace

TEST(VmmVarianceAware, ExactSecondMomentFieldGivesItsSquareRootsWeights) {
    // sqrt(E[L^2])(w) = s_1 v_1(w) + s_2 v_2(w) with s = (1, 2): second-moment samples on an
    // equal-area grid (p uniform) carry E[L^2] / p. The mixture starts with the radiance weights 1/2, 1/2.
    const Vmm shape = variance_aware_two_lobes(1.f / 3.f, 2.f / 3.f);
    std::vector<DirectionalSample> samples;
    for (const Vec3f& w : variance_aware_grid(4000, 8)) {
        const double root = 3.0 * double(shape.eval(w));  // s_1 v_1 + s_2 v_2
        samples.push_back({w, float(root * root * 4.0 * double(Pi))});
    }
    Vmm vmm = variance_aware_two_lobes(0.5f, 0.5f);
    ASSERT_TRUE(variance_aware_weights(vmm, samples));
    EXPECT_NEAR(vmm.weight[0], 1.f / 3.f, 0.01f);
    EXPECT_NEAR(vmm.weight[1], 2.f / 3.f, 0.01f);
    // The lobes themselves are untouched.
    EXPECT_EQ(vmm.kappa[0], 0.8f);
    EXPECT_EQ(vmm.mu_z[1], -1.f);
}

TEST(VmmVarianceAware, NoisyEstimatesShiftWeightTowardsTheNoisyLobe) {
    // E[L^](w) = V(w) = v_1 / 2 + v_2 / 2, the radiance mixture. Directions from p = 1/2 uniform + 1/2 V.
    // Noise-free: L^ = V, so sqrt(E[L^2]) = V and the weights stay 1/2, 1/2. Noisy: the narrow lobe's
    // light arrives through a path that finds it with probability q = 1/4, L^ = v_1 / 2 + (v_2 / 2) B / q
    // (B ~ Bernoulli(q)), so E[L^2] = (v_1 / 2 + v_2)^2 - v_1 v_2 / 2 ~ (v_1 / 2 + v_2)^2 (the cross
    // term integrates to < 1 % of v_2^2): weights 1/3, 2/3.
    const Vmm radiance = variance_aware_two_lobes(0.5f, 0.5f);
    std::vector<DirectionalSample> clean, noisy;
    for (int i = 0; i < 200000; ++i) {
        Sampler s(11, 0, uint64_t(i));
        const Vec3f w = s.next_1d() < 0.5f ? warp::square_to_uniform_sphere(s.next_2d()) : radiance.sample(s.next_2d());
        const double p = 0.5 * double(InvFourPi) + 0.5 * double(radiance.pdf(w));
        const double L1 = 0.5 * double(radiance.lobe(0).eval(w)), L2 = 0.5 * double(radiance.lobe(1).eval(w));
        clean.push_back({w, float((L1 + L2) * (L1 + L2) / p)});
        const double q = 0.25, L = L1 + (s.next_1d() < q ? L2 / q : 0.0);
        noisy.push_back({w, float(L * L / p)});
    }
    Vmm a = radiance, b = radiance;
    ASSERT_TRUE(variance_aware_weights(a, clean));
    ASSERT_TRUE(variance_aware_weights(b, noisy));
    EXPECT_NEAR(a.weight[0], 0.5f, 0.01f);
    EXPECT_NEAR(b.weight[0], 1.f / 3.f, 0.02f);
    EXPECT_NEAR(b.weight[1], 2.f / 3.f, 0.02f);
}

TEST(VmmVarianceAware, NoSecondMomentLeavesTheMixture) {
    Vmm vmm = variance_aware_two_lobes(0.3f, 0.7f);
    const std::vector<DirectionalSample> zero(10, DirectionalSample{Vec3f(0.f, 0.f, 1.f), 0.f});
    EXPECT_FALSE(variance_aware_weights(vmm, zero));
    EXPECT_FALSE(variance_aware_weights(vmm, {}));
    EXPECT_EQ(vmm.weight[0], 0.3f);
    EXPECT_EQ(vmm.weight[1], 0.7f);
}
