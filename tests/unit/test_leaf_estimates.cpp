// LeafEstimates: the exact mode reads exactly what InscatterCache and the field give; the tables
// (octahedral, bilinear, 16-bit) stay close to the exact values for smooth radiance (they only
// shape probabilities, but a table that drifted far would quietly make guiding useless); invalid
// leaves read nothing; the octahedral map round-trips.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "support/turning_light_field.h"
#include "volguide/guiding/leaf_estimates.h"

using namespace volguide;

namespace {

// Radiance from a direction that turns with x, a moderately sharp lobe plus a uniform part.
GuidingField estimates_test_field(float kappa) {
    return test::turning_light_field(kappa, 1.f, 1500, 6);
}

}  // namespace

TEST(LeafEstimates, OctahedralMapRoundTrips) {
    for (int i = 0; i < 2000; ++i) {
        Sampler s(5, 0, uint64_t(i));
        const Vec3f w = warp::square_to_uniform_sphere(s.next_2d());
        const Point2f uv = octahedral_encode(w);
        ASSERT_GE(uv.x, 0.f);
        ASSERT_LE(uv.x, 1.f);
        ASSERT_GE(uv.y, 0.f);
        ASSERT_LE(uv.y, 1.f);
        const Vec3f back = octahedral_decode(uv);
        EXPECT_NEAR(dot(back, w), 1.f, 1e-5f) << w.x << " " << w.y << " " << w.z;
    }
}

TEST(LeafEstimates, ExactModeEqualsTheCacheAndTheField) {
    const GuidingField field = estimates_test_field(30.f);
    const InscatterCache cache(field, hg_phase_vmm(0.6f));
    const LeafEstimates exact(field, cache, 0);
    for (int i = 0; i < 300; ++i) {
        Sampler s(3, 1, uint64_t(i));
        const Point3f x(2.f * s.next_1d(), s.next_1d(), s.next_1d());
        const Vec3f w = warp::square_to_uniform_sphere(s.next_2d());
        const int leaf = field.tree().leaf_at(x);
        Color3 Li(-1.f), L(-1.f);
        const bool valid = exact.lookup(leaf, w, Li, L);
        ASSERT_EQ(valid, field.leaves()[size_t(leaf)].valid);
        if (!valid) continue;
        EXPECT_EQ(Li, cache.inscattered(leaf, w));
        EXPECT_EQ(L, GuidingField::incident(field.leaves()[size_t(leaf)], w));
    }
}

// Smooth radiance (kappa 5 lobes; g = 0.6 convolution): the tables converge to the exact values at
// the bilinear rate (RMS error / 4 per doubling of the resolution, asked: / 2.5), and at 16x16 the
// RMS error is a few per cent of each leaf's peak. A wrong mapping or a transposed table would not
// converge at all.
TEST(LeafEstimates, TablesConvergeToTheExactValues) {
    const GuidingField field = estimates_test_field(5.f);
    const InscatterCache cache(field, hg_phase_vmm(0.6f));
    const LeafEstimates exact(field, cache, 0);
    const int resolutions[3] = {8, 16, 32};
    double sq_i[3] = {0, 0, 0}, sq_l[3] = {0, 0, 0};
    int n = 0;
    for (int r = 0; r < 3; ++r) {
        const LeafEstimates table(field, cache, resolutions[r]);
        for (int l = 0; l < field.tree().leaf_count(); ++l) {
            Color3 Li, L;
            if (!exact.lookup(l, Vec3f(0.f, 0.f, 1.f), Li, L)) continue;
            std::vector<Vec3f> dirs;
            float peak_i = 0.f, peak_l = 0.f;
            for (int i = 0; i < 2000; ++i) {
                Sampler s(4, uint64_t(l), uint64_t(i));
                dirs.push_back(warp::square_to_uniform_sphere(s.next_2d()));
                exact.lookup(l, dirs.back(), Li, L);
                peak_i = std::max(peak_i, Li.average());
                peak_l = std::max(peak_l, L.average());
            }
            for (const Vec3f& w : dirs) {
                Color3 Lit, Lt;
                exact.lookup(l, w, Li, L);
                ASSERT_TRUE(table.lookup(l, w, Lit, Lt));
                sq_i[r] += std::pow((Lit.average() - Li.average()) / peak_i, 2.f);
                sq_l[r] += std::pow((Lt.average() - L.average()) / peak_l, 2.f);
                n += r == 0;
            }
        }
    }
    ASSERT_GT(n, 8000);
    double rms_i[3], rms_l[3];
    for (int r = 0; r < 3; ++r) {
        rms_i[r] = std::sqrt(sq_i[r] / n);
        rms_l[r] = std::sqrt(sq_l[r] / n);
        std::cout << resolutions[r] << "x" << resolutions[r] << ": RMS error / peak: in-scattered " << rms_i[r]
                  << ", incident " << rms_l[r] << "\n";
    }
    for (int r = 0; r < 2; ++r) {
        EXPECT_GT(rms_i[r], 2.5 * rms_i[r + 1]) << resolutions[r];
        EXPECT_GT(rms_l[r], 2.5 * rms_l[r + 1]) << resolutions[r];
    }
    // Measured 0.6 % and 0.9 % (a transposed or shifted table: tens of per cent).
    EXPECT_LT(rms_i[1], 0.015);
    EXPECT_LT(rms_l[1], 0.015);
}

TEST(LeafEstimates, InvalidLeavesAndNegativeIndicesReadNothing) {
    const GuidingField field = estimates_test_field(30.f);
    const InscatterCache cache(field, hg_phase_vmm(0.f));
    for (int resolution : {0, 8}) {
        const LeafEstimates estimates(field, cache, resolution);
        Color3 Li(7.f), L(7.f);
        EXPECT_FALSE(estimates.lookup(-1, Vec3f(0.f, 0.f, 1.f), Li, L));
        for (int l = 0; l < field.tree().leaf_count(); ++l)
            if (!field.leaves()[size_t(l)].valid) {
                EXPECT_FALSE(estimates.lookup(l, Vec3f(0.f, 0.f, 1.f), Li, L));
            }
        EXPECT_EQ(Li, Color3(7.f));
        EXPECT_EQ(L, Color3(7.f));
    }
}
