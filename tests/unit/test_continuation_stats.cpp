// rrs=ears's statistics (integrators/guided/estimates/continuation_stats.h, continuation_recorder.h;
// docs/theory.md §9.8): the direction bins, the moments against known integrals, exact sums in any
// order, the recorder's split-tree bookkeeping on a scripted camera sample, the factor and the branch
// budget from known moments.
#include <gtest/gtest.h>

#include <cmath>

#include "volguide/core/sampler.h"
#include "volguide/integrators/guided/estimates/continuation_recorder.h"
#include "volguide/integrators/guided/estimates/continuation_stats.h"

using namespace volguide;

namespace {

constexpr ContinuationStage kDistance = ContinuationStage::Distance;
constexpr ContinuationStage kDirection = ContinuationStage::Direction;

}  // namespace

TEST(ContinuationStats, CubeMapBinsSeparateTheSixAxes) {
    const Vec3f axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(continuation_direction_bin(axes[i]), i);
        // A direction tilted towards another axis stays in its dominant axis' bin.
        const Vec3f tilted = normalize(axes[i] + 0.5f * axes[(i + 2) % 6]);
        EXPECT_EQ(continuation_direction_bin(tilted), i);
    }
}

// y uniform in [0, 1): E[y] = 1/2, E[y^2] = 1/3; the cost is summed exactly.
TEST(ContinuationStats, MomentsMatchKnownIntegrals) {
    ContinuationStatistics stats(3);
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        Sampler s(7, 0, uint64_t(i));
        stats.add_point(kDirection, 1, 4, double(s.next_1d()), 3);
    }
    const ContinuationMoments& m = stats.moments(kDirection, 1, 4);
    ASSERT_EQ(m.n, uint64_t(n));
    EXPECT_NEAR(m.sum.value() / n, 0.5, 4.0 * std::sqrt(1.0 / 12.0 / n));
    EXPECT_NEAR(m.sum_sq.value() / n, 1.0 / 3.0, 4.0 * std::sqrt(4.0 / 45.0 / n));
    EXPECT_EQ(m.cost, uint64_t(3 * n));
    // Nothing leaked into the other stage, cell or bin.
    EXPECT_EQ(stats.moments(kDistance, 1, 4).n, 0u);
    EXPECT_EQ(stats.moments(kDirection, 0, 4).n, 0u);
    EXPECT_EQ(stats.moments(kDirection, 1, 3).n, 0u);
}

// The same terms split over two "threads" in another order give the same bits.
TEST(ContinuationStats, SumsAreExactInAnyOrder) {
    ContinuationStatistics forward(2), a(2), b(2);
    std::vector<double> ys;
    for (int i = 0; i < 5000; ++i) {
        Sampler s(3, 1, uint64_t(i));
        ys.push_back(std::pow(10.0, 6.0 * double(s.next_1d()) - 3.0));  // 1e-3 .. 1e3
    }
    for (double y : ys) forward.add_point(kDistance, 0, 2, y, 1);
    for (size_t i = ys.size(); i-- > 0;) (i % 3 ? a : b).add_point(kDistance, 0, 2, ys[i], 1);
    ContinuationStatistics merged(2);
    merged += b;
    merged += a;
    EXPECT_EQ(merged.moments(kDistance, 0, 2).sum.value(), forward.moments(kDistance, 0, 2).sum.value());
    EXPECT_EQ(merged.moments(kDistance, 0, 2).sum_sq.value(), forward.moments(kDistance, 0, 2).sum_sq.value());
    EXPECT_EQ(merged.moments(kDistance, 0, 2).n, forward.moments(kDistance, 0, 2).n);
}

// A scripted camera sample: a contribution before any point, a distance-stage point (weight 0.5)
// split in two, the original reaching a direction-stage point (weight 0.25). Each copy is one sample
// of its point; subtrees include their children; the root counts everything.
TEST(ContinuationStats, RecorderCreditsEachCopyWithItsSubtree) {
    ContinuationStatistics stats(3);  // leaves 0, 1 and "outside"
    PixelMoments pixels(2, 1);
    ContinuationRecorder rec(stats, pixels);
    rec.begin(nullptr, 1, 2.f);
    rec.record_contribution(Color3(0.2f));
    rec.record_medium_hit(MediumInteraction());
    rec.record_continuation(kDistance, VertexLeaf{0}, Vec3f(1, 0, 0), 0.f, Color3(0.5f));
    const int copy = rec.branch_point();
    rec.record_medium_hit(MediumInteraction());
    rec.record_contribution(Color3(0.3f));
    rec.record_continuation(kDirection, VertexLeaf{0}, Vec3f(0, 1, 0), 0.f, Color3(0.25f));
    rec.record_surface_hit(SurfaceInteraction());
    rec.record_contribution(Color3(0.1f));
    rec.resume_branch(copy);
    rec.record_medium_hit(MediumInteraction());
    rec.record_contribution(Color3(0.4f));
    rec.end_camera_sample(2);
    rec.end();

    const ContinuationMoments& d = stats.moments(kDistance, 0, 0);
    ASSERT_EQ(d.n, 2u);  // the original (0.3 + 0.1) / 0.5 and the copy 0.4 / 0.5
    EXPECT_NEAR(d.sum.value(), 1.6, 1e-6);
    EXPECT_NEAR(d.sum_sq.value(), 1.28, 1e-6);
    EXPECT_EQ(d.cost, 3u);  // 2 events in the original's subtree, 1 in the copy's
    const ContinuationMoments& w = stats.moments(kDirection, 0, 2);
    ASSERT_EQ(w.n, 1u);
    EXPECT_NEAR(w.sum.value(), 0.4, 1e-6);
    EXPECT_EQ(w.cost, 1u);
    EXPECT_EQ(stats.camera_samples(), 1u);
    EXPECT_EQ(stats.cost(), 4u);
    EXPECT_EQ(stats.branches(), 2u);
    // The pixel's sample: X / I = 1.0 / 2; a leaf outside the field goes to the last cell.
    const PixelMoments::Pixel px = pixels.at(1);
    EXPECT_EQ(px.n, 1.0);
    EXPECT_NEAR(px.sum, 0.5, 1e-4);
    EXPECT_EQ(pixels.at(0).n, 0.0);
    rec.begin(nullptr, -1, 1.f);
    rec.record_continuation(kDistance, VertexLeaf{-1}, Vec3f(0, 0, -1), 0.f, Color3(1.f));
    rec.record_contribution(Color3(1.f));
    rec.end();
    EXPECT_EQ(stats.moments(kDistance, 2, 5).n, 1u);
}

TEST(ContinuationStats, PixelOfFilmPosition) {
    PixelMoments pixels(4, 2);
    EXPECT_EQ(pixels.pixel(Point2f(0.f, 0.f)), 0);
    EXPECT_EQ(pixels.pixel(Point2f(0.99f, 0.99f)), 7);
    EXPECT_EQ(pixels.pixel(Point2f(0.3f, 0.6f)), 5);
    EXPECT_EQ(pixels.pixel(Point2f(-0.01f, 0.5f)), -1);  // a filter's border
    EXPECT_EQ(pixels.pixel(Point2f(0.5f, 1.f)), -1);
}

namespace {

// A cell whose continuations collect 0 or 2 (mean 1, M2 2, Var 1) at cost 4 each, and one pixel
// whose samples x are 0 or 2 (variance 2, mean 1: the learned estimate is I) at cost 8 per camera
// sample: r = sqrt(2 / 4), s = sqrt(1 / 4), sqrt(C_image / V_image) = 2.
ContinuationSnapshot known_snapshot(const EarsSettings& settings, ContinuationStatistics& stats) {
    PixelMoments pixels(1, 1);
    for (int i = 0; i < 64; ++i) {
        stats.add_point(kDistance, 0, 1, (i % 2) ? 2.0 : 0.0, 4);
        stats.add_camera_sample(8, 1);
        pixels.add(0, (i % 2) ? 2.0 : 0.0);
    }
    return ContinuationSnapshot::from(stats, pixels, settings, 8.0);
}

}  // namespace

TEST(ContinuationStats, FactorFromKnownMoments) {
    EarsSettings settings;
    settings.min_samples = 32;
    ContinuationStatistics stats(2);
    const ContinuationSnapshot snap = known_snapshot(settings, stats);
    EXPECT_NEAR(snap.image_variance(), 64.0 / 63.0, 1e-4);  // the sample variance of the 0s and 2s
    EXPECT_DOUBLE_EQ(snap.image_cost(), 8.0);
    EXPECT_EQ(snap.learned_points(), 1u);
    const float img = float(std::sqrt(8.0 / snap.image_variance()));
    // Roulette below 1: q = T r img.
    EXPECT_NEAR(snap.factor(kDistance, 0, 1, 0.25f), 0.25f * std::sqrt(0.5f) * img, 1e-5f);
    // Splitting by the variance where both ask for it: T = 4 gives q_r > 1 and q_s = 4 * 0.5 * img.
    EXPECT_NEAR(snap.factor(kDistance, 0, 1, 4.f), 4.f * 0.5f * img, 1e-5f);
    // The second moment asks for splitting, the variance does not: no decision (q = 1).
    const float t = 1.2f / (std::sqrt(0.5f) * img);
    ASSERT_LT(t * 0.5f * img, 1.f);
    EXPECT_EQ(snap.factor(kDistance, 0, 1, t), 1.f);
    // Another stage, bin or cell has no statistics: the fallback.
    EXPECT_LT(snap.factor(kDirection, 0, 1, 1.f), 0.f);
    EXPECT_LT(snap.factor(kDistance, 0, 2, 1.f), 0.f);
    EXPECT_LT(snap.factor(kDistance, 1, 1, 1.f), 0.f);
    // Too few samples: the fallback.
    settings.min_samples = 65;
    ContinuationStatistics few(2);
    EXPECT_LT(known_snapshot(settings, few).factor(kDistance, 0, 1, 1.f), 0.f);
    // Nothing learned at all.
    EXPECT_LT(ContinuationSnapshot().factor(kDistance, 0, 1, 1.f), 0.f);
}

// The learned pixel estimate: the pixel's mean x shrunk towards 1 by the prior samples.
TEST(ContinuationStats, LearnedPixelEstimate) {
    EarsSettings settings;
    settings.pixel_prior = 4.0;
    PixelMoments pixels(2, 1);
    for (int i = 0; i < 12; ++i) pixels.add(0, 3.0);  // the field's I is 3x too dark here
    ContinuationStatistics stats(1);
    const ContinuationSnapshot snap = ContinuationSnapshot::from(stats, pixels, settings, 0.0);
    EXPECT_NEAR(snap.pixel_estimate(0, 2.f), 2.f * (4.f + 36.f) / (4.f + 12.f), 1e-4f);
    EXPECT_FLOAT_EQ(snap.pixel_estimate(1, 2.f), 2.f);   // no samples: I
    EXPECT_FLOAT_EQ(snap.pixel_estimate(-1, 2.f), 2.f);  // outside the film: I
}

// The adaptive budget: budget_factor x C_0 over the measured cost per branch, within
// [min_budget, max_branches]; a fixed budget replaces it.
TEST(ContinuationStats, BranchBudgetFromMeasuredCost) {
    EarsSettings settings;
    settings.budget_factor = 8.f;
    settings.min_budget = 4.f;
    settings.max_branches = 64;
    ContinuationStatistics stats(1);
    PixelMoments pixels(1, 1);
    for (int i = 0; i < 10; ++i) stats.add_camera_sample(12, 3);  // 4 events per branch
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 6.0).branch_budget(), 12.f);
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 1.0).branch_budget(), 4.f);
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 100.0).branch_budget(), 64.f);
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 0.0).branch_budget(), 4.f);  // C_0 unknown
    settings.fixed_budget = 3.f;
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 6.0).branch_budget(), 3.f);
}
