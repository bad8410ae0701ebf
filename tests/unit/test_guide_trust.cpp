// The guided decisions' fallback rule (guide_trust.h): the directional contrast of a VMM against
// closed forms and quadrature, and the trust's two factors.
#include <gtest/gtest.h>

#include <cmath>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/guiding/guide_trust.h"
#include "volguide/vmm/vmf.h"

using namespace volguide;

namespace {

// chi2 by Monte Carlo over uniform directions: 4 pi E_uniform[V^2] - 1.
double contrast_by_quadrature(const Vmm& vmm, int n) {
    double s = 0;
    for (int i = 0; i < n; ++i) {
        Sampler sampler(5, 0, uint64_t(i));
        const Vec3f w = warp::square_to_uniform_sphere(sampler.next_2d());
        const double v = vmm.eval(w);
        s += v * v;
    }
    return 4.0 * M_PI * 4.0 * M_PI * s / n - 1.0;
}

TEST(GuideTrust, ContrastOfTheUniformDensityIsZero) {
    Vmm uniform;
    uniform.add_lobe(1.f, VmfLobe(Vec3f(0, 0, 1), 0.f));
    EXPECT_NEAR(directional_contrast(uniform), 0.0, 1e-6);
    EXPECT_EQ(directional_contrast(Vmm()), 0.0);
}

TEST(GuideTrust, ContrastOfOneLobeIsItsClosedForm) {
    // ∫ v^2 = c~(k)^2 / c~(2k) for a single lobe of concentration k.
    for (float kappa : {0.5f, 3.f, 40.f}) {
        Vmm one;
        one.add_lobe(1.f, VmfLobe(normalize(Vec3f(1, 2, 3)), kappa));
        const double c = vmf_normalization(kappa);
        EXPECT_NEAR(directional_contrast(one), 4.0 * M_PI * c * c / vmf_normalization(2.0 * kappa) - 1.0,
                    1e-4 * (1.0 + kappa))
            << "kappa " << kappa;
    }
}

TEST(GuideTrust, ContrastOfAMixtureMatchesQuadrature) {
    Vmm mix;
    mix.add_lobe(0.5f, VmfLobe(Vec3f(0, 0, 1), 4.f));
    mix.add_lobe(0.3f, VmfLobe(Vec3f(1, 0, 0), 10.f));
    mix.add_lobe(0.2f, VmfLobe(Vec3f(0, 0, 1), 0.f));
    const double q = contrast_by_quadrature(mix, 400000);
    EXPECT_NEAR(directional_contrast(mix), q, 0.03 * q);
}

TEST(GuideTrust, NothingToGuideBelowTheContrastThresholdFullTrustFromTwiceIt) {
    const GuideTrustSettings s{1.f, 0.5f};
    EXPECT_EQ(guide_trust(0.5f, 0.2, s), 0.f);
    EXPECT_EQ(guide_trust(0.5f, 0.5, s), 0.f);
    EXPECT_NEAR(guide_trust(0.5f, 0.75, s), 0.5f, 1e-6f);
    EXPECT_EQ(guide_trust(0.5f, 1.0, s), 1.f);
    EXPECT_EQ(guide_trust(0.5f, 30.0, s), 1.f);
}

TEST(GuideTrust, OpticallyLargeLeavesAreTrustedInProportionToTauMaxOverTheirSize) {
    const GuideTrustSettings s{1.f, 0.5f};
    EXPECT_EQ(guide_trust(1.f, 5.0, s), 1.f);
    EXPECT_NEAR(guide_trust(4.f, 5.0, s), 0.25f, 1e-6f);
    EXPECT_NEAR(guide_trust(4.f, 0.75, s), 0.125f, 1e-6f);
    // Either factor off.
    EXPECT_EQ(guide_trust(4.f, 0.1, GuideTrustSettings{0.f, 0.5f}), 0.f);
    EXPECT_NEAR(guide_trust(4.f, 0.1, GuideTrustSettings{1.f, 0.f}), 0.25f, 1e-6f);
}

}  // namespace
