// The four-lanes mixture kernel (vmm/vmf_sum.h): its exp against std::exp (within 2 ulp down to
// FLT_MIN, flushed to 0 below), NaN and range ends, and vmf_sum against the one-lobe-at-a-time
// float sum with std::exp for every count (lane tails included): they differ by rounding only.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/vmm/vmf_sum.h"

using namespace volguide;

namespace {
int64_t ulp_distance(float a, float b) {
    int32_t ia, ib;
    std::memcpy(&ia, &a, 4);
    std::memcpy(&ib, &b, 4);
    return std::abs(int64_t(ia) - int64_t(ib));  // both >= 0 here
}
}  // namespace

TEST(VmfSum, ExpWithinTwoUlpOfStdExp) {
    int64_t worst = 0;
    float worst_x = 0.f;
    for (float x = 0.f; x > -110.f; x -= 1.3e-5f) {
        const float want = std::exp(x), got = vmf_exp(x);
        if (want < std::numeric_limits<float>::min()) {  // denormal results are flushed
            ASSERT_TRUE(got == 0.f || ulp_distance(got, std::numeric_limits<float>::min()) <= 2) << x;
            continue;
        }
        const int64_t d = ulp_distance(got, want);
        if (d > worst) worst = d, worst_x = x;
    }
    EXPECT_LE(worst, 2) << "at x = " << worst_x;
    // Every float in the reduced range's first octave, exhaustively near 0 (r ~ x).
    for (float x = -1e-30f; x > -0.7f; x = std::nextafter(x * 1.0001f, -1.f))
        ASSERT_LE(ulp_distance(vmf_exp(x), std::exp(x)), 2) << x;
}

TEST(VmfSum, ExpEnds) {
    EXPECT_EQ(vmf_exp(0.f), 1.f);
    EXPECT_EQ(vmf_exp(-0.f), 1.f);
    EXPECT_EQ(vmf_exp(-200.f), 0.f);
    EXPECT_EQ(vmf_exp(-std::numeric_limits<float>::infinity()), 0.f);
    EXPECT_TRUE(std::isnan(vmf_exp(std::numeric_limits<float>::quiet_NaN())));
    EXPECT_NEAR(vmf_exp(1.f), std::exp(1.f), 2e-7f * std::exp(1.f));  // positive arguments work too
}

TEST(VmfSum, EqualsTheLobeSumForEveryCount) {
    Sampler s(7, 0, 0);
    for (int count = 0; count <= 13; ++count) {
        std::vector<float> mx, my, mz, k, wt, nm;
        for (int i = 0; i < count; ++i) {
            const Vec3f mu = warp::square_to_uniform_sphere(s.next_2d());
            mx.push_back(mu.x), my.push_back(mu.y), mz.push_back(mu.z);
            k.push_back(std::pow(1000.f, s.next_1d()) - 1.f);
            wt.push_back(s.next_1d());
            nm.push_back(0.1f + s.next_1d());
        }
        for (int q = 0; q < 50; ++q) {
            const Vec3f w = warp::square_to_uniform_sphere(s.next_2d());
            // The scalar formula VmfMixture::eval used before, one lobe at a time with std::exp.
            float want = 0.f, want_unweighted = 0.f;
            for (int i = 0; i < count; ++i) {
                const float dx = w.x - mx[i], dy = w.y - my[i], dz = w.z - mz[i];
                const float e = std::exp(-k[i] * std::min(0.5f * (dx * dx + dy * dy + dz * dz), 2.f));
                want += wt[i] * nm[i] * e;
                want_unweighted += nm[i] * e;
            }
            const float got = vmf_sum(mx.data(), my.data(), mz.data(), k.data(), wt.data(), nm.data(), count, w);
            const float got_unweighted = vmf_sum(mx.data(), my.data(), mz.data(), k.data(), nullptr, nm.data(), count, w);
            EXPECT_NEAR(got, want, 1e-6f * want + 1e-30f) << "count " << count;
            EXPECT_NEAR(got_unweighted, want_unweighted, 1e-6f * want_unweighted + 1e-30f) << "count " << count;
        }
    }
}
