// Equiangular distance sampling (integrators/volpath/equiangular.h): the density integrates to one over
// [0, tmax] (finite and infinite), and samples follow it (Kolmogorov–Smirnov against the CDF obtained
// by integrating pdf() numerically, α = 0.01).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/integrators/volpath/equiangular.h"

using namespace volguide;

namespace {

struct Config {
    Point3f o;
    Vec3f d;
    float tmax;
    Point3f c;
};

// Midpoint rule on [0, T] with a substitution t = T u / (1 - u) for infinite intervals.
double integrate_pdf(const EquiangularSampler& eq, float tmax, double upto) {
    const int n = 200000;
    double sum = 0;
    if (std::isinf(tmax)) {
        const double umax = upto / (1.0 + upto);  // t = u / (1 - u)
        for (int i = 0; i < n; ++i) {
            const double u = (i + 0.5) / n * umax, t = u / (1 - u);
            sum += eq.pdf(float(t)) / ((1 - u) * (1 - u)) * umax / n;
        }
    } else {
        const double hi = std::min<double>(upto, tmax);
        for (int i = 0; i < n; ++i) sum += eq.pdf(float((i + 0.5) / n * hi)) * hi / n;
    }
    return sum;
}

const Config kConfigs[] = {
    {Point3f(0.f), Vec3f(1.f, 0.f, 0.f), 5.f, Point3f(2.f, 1.f, 0.f)},        // light beside the segment
    {Point3f(0.f), Vec3f(1.f, 0.f, 0.f), Infinity, Point3f(1.f, 1.f, 0.f)},   // infinite segment
    {Point3f(0.f), Vec3f(0.f, 0.f, 1.f), 3.f, Point3f(0.2f, 0.f, -2.f)},     // light behind the origin
    {Point3f(1.f, 2.f, 3.f), normalize(Vec3f(1.f, 1.f, 0.f)), 10.f, Point3f(4.f, 5.f, 3.05f)},  // close to the line
};

}  // namespace

TEST(EquiangularSampling, NormalisedAndOutsideIsZero) {
    for (const Config& cfg : kConfigs) {
        EquiangularSampler eq(cfg.o, cfg.d, cfg.tmax, cfg.c);
        ASSERT_TRUE(eq.valid());
        EXPECT_NEAR(integrate_pdf(eq, cfg.tmax, 1e7), 1.0, 2e-3);
        EXPECT_EQ(eq.pdf(-0.1f), 0.f);
        if (!std::isinf(cfg.tmax)) {
            EXPECT_EQ(eq.pdf(cfg.tmax * 1.01f), 0.f);
        }
    }
}

TEST(EquiangularSampling, KolmogorovSmirnov) {
    for (const Config& cfg : kConfigs) {
        EquiangularSampler eq(cfg.o, cfg.d, cfg.tmax, cfg.c);
        const int n = 20000;
        std::vector<float> t(n);
        Sampler sampler(7, 0, 0);
        for (float& x : t) {
            x = eq.sample(sampler.next_1d());
            ASSERT_TRUE(x >= 0.f && x <= cfg.tmax);
        }
        std::sort(t.begin(), t.end());
        // Check the empirical CDF at 40 quantile positions against the integrated pdf.
        double d_max = 0;
        for (int k = 1; k < 40; ++k) {
            const int i = k * n / 40;
            const double cdf = integrate_pdf(eq, cfg.tmax, t[i]);
            d_max = std::max(d_max, std::abs(cdf - double(i) / n));
        }
        EXPECT_LT(d_max, 1.63 / std::sqrt(double(n)) + 2e-3) << "KS distance";
    }
}

TEST(EquiangularSampling, DegenerateOnTheLine) {
    EquiangularSampler eq(Point3f(0.f), Vec3f(1.f, 0.f, 0.f), 5.f, Point3f(2.f, 0.f, 0.f));
    EXPECT_FALSE(eq.valid());
    EXPECT_EQ(eq.pdf(1.f), 0.f);
}
