// The directional contrast of a VMM (vmm_contrast.h) against closed forms and quadrature.
#include <gtest/gtest.h>

#include <cmath>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/vmm/vmm_contrast.h"
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

TEST(VmmContrast, ContrastOfTheUniformDensityIsZero) {
    Vmm uniform;
    uniform.add_lobe(1.f, VmfLobe(Vec3f(0, 0, 1), 0.f));
    EXPECT_NEAR(directional_contrast(uniform), 0.0, 1e-6);
    EXPECT_EQ(directional_contrast(Vmm()), 0.0);
}

TEST(VmmContrast, ContrastOfOneLobeIsItsClosedForm) {
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

TEST(VmmContrast, ContrastOfAMixtureMatchesQuadrature) {
    Vmm mix;
    mix.add_lobe(0.5f, VmfLobe(Vec3f(0, 0, 1), 4.f));
    mix.add_lobe(0.3f, VmfLobe(Vec3f(1, 0, 0), 10.f));
    mix.add_lobe(0.2f, VmfLobe(Vec3f(0, 0, 1), 0.f));
    const double q = contrast_by_quadrature(mix, 400000);
    EXPECT_NEAR(directional_contrast(mix), q, 0.03 * q);
}

}  // namespace
