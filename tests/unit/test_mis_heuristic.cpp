// The power heuristic (beta = 2) at the extremes: delta strategies, zero densities, and finite
// densities whose float squares overflow (a grazing area-light sample reached pdf ~1e20 in the
// `sss` benchmark scene and made a NaN pixel before the squares were taken in double).
#include <gtest/gtest.h>

#include <cmath>

#include "volguide/core/math.h"

namespace volguide {
namespace {

TEST(MisPowerHeuristic, OrdinaryValues) {
    EXPECT_FLOAT_EQ(mis_power_heuristic(1.f, 1.f), 0.5f);
    EXPECT_FLOAT_EQ(mis_power_heuristic(3.f, 1.f), 0.9f);
    EXPECT_FLOAT_EQ(mis_power_heuristic(1.f, 3.f), 0.1f);
    EXPECT_FLOAT_EQ(mis_power_heuristic(0.f, 0.f), 0.f);
    EXPECT_FLOAT_EQ(mis_power_heuristic(0.f, 2.f), 0.f);
}

TEST(MisPowerHeuristic, InfiniteAndHugeDensitiesStayFiniteAndComplementary) {
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(mis_power_heuristic(inf, 5.f), 1.f);
    EXPECT_EQ(mis_power_heuristic(5.f, inf), 0.f);
    for (float big : {1e19f, 1e20f, 1e30f, 3e38f}) {
        const float w = mis_power_heuristic(big, 1.f), v = mis_power_heuristic(1.f, big);
        ASSERT_TRUE(std::isfinite(w)) << big;
        EXPECT_FLOAT_EQ(w, 1.f) << big;
        EXPECT_NEAR(v, 0.f, 1e-30f) << big;
        EXPECT_FLOAT_EQ(mis_power_heuristic(big, big), 0.5f) << big;
        EXPECT_FLOAT_EQ(mis_power_heuristic(big, 2.f * big) + mis_power_heuristic(2.f * big, big), 1.f) << big;
    }
}

}  // namespace
}  // namespace volguide
