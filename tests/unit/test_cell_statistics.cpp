// The learner's cell statistics and recorder (integrators/guided/estimates/cell_statistics.h,
// cell_recorder.h) and rrs=ears's snapshot of them (continuation_snapshot.h; docs/theory.md §9.8): the
// direction bins, the moments against known integrals, exact sums in any order, the recorder's
// split-tree bookkeeping on a scripted camera sample (continuations, decisions, the cost in decisions),
// the factor and the branch budget from known moments.
#include <gtest/gtest.h>

#include <cmath>

#include "volguide/core/sampler.h"
#include "volguide/integrators/guided/estimates/cell_recorder.h"
#include "volguide/integrators/guided/estimates/continuation_snapshot.h"

using namespace volguide;

namespace {

constexpr ContinuationStage kDistance = ContinuationStage::Distance;
constexpr ContinuationStage kDirection = ContinuationStage::Direction;

}  // namespace

TEST(CellStatistics, CubeMapBinsSeparateTheSixAxes) {
    const Vec3f axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(continuation_direction_bin(axes[i]), i);
        // A direction tilted towards another axis stays in its dominant axis' bin.
        const Vec3f tilted = normalize(axes[i] + 0.5f * axes[(i + 2) % 6]);
        EXPECT_EQ(continuation_direction_bin(tilted), i);
    }
}

// y uniform in [0, 1): E[y] = 1/2, E[y^2] = 1/3; the cost is summed exactly.
TEST(CellStatistics, MomentsMatchKnownIntegrals) {
    CellStatistics stats(3);
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        Sampler s(7, 0, uint64_t(i));
        stats.add_continuation(kDirection, 1, 4, double(s.next_1d()), 3);
    }
    const ContinuationMoments& m = stats.continuation(kDirection, 1, 4);
    ASSERT_EQ(m.n, uint64_t(n));
    EXPECT_NEAR(m.sum.value() / n, 0.5, 4.0 * std::sqrt(1.0 / 12.0 / n));
    EXPECT_NEAR(m.sum_sq.value() / n, 1.0 / 3.0, 4.0 * std::sqrt(4.0 / 45.0 / n));
    EXPECT_EQ(m.cost, uint64_t(3 * n));
    // Nothing leaked into the other stage, cell or bin.
    EXPECT_EQ(stats.continuation(kDistance, 1, 4).n, 0u);
    EXPECT_EQ(stats.continuation(kDirection, 0, 4).n, 0u);
    EXPECT_EQ(stats.continuation(kDirection, 1, 3).n, 0u);
}

// The same terms split over two "threads" in another order give the same bits.
TEST(CellStatistics, SumsAreExactInAnyOrder) {
    CellStatistics forward(2), a(2), b(2);
    std::vector<double> ys;
    for (int i = 0; i < 5000; ++i) {
        Sampler s(3, 1, uint64_t(i));
        ys.push_back(std::pow(10.0, 6.0 * double(s.next_1d()) - 3.0));  // 1e-3 .. 1e3
    }
    for (double y : ys) forward.add_continuation(kDistance, 0, 2, y, 1);
    for (size_t i = ys.size(); i-- > 0;) (i % 3 ? a : b).add_continuation(kDistance, 0, 2, ys[i], 1);
    CellStatistics merged(2);
    merged += b;
    merged += a;
    EXPECT_EQ(merged.continuation(kDistance, 0, 2).sum.value(), forward.continuation(kDistance, 0, 2).sum.value());
    EXPECT_EQ(merged.continuation(kDistance, 0, 2).sum_sq.value(), forward.continuation(kDistance, 0, 2).sum_sq.value());
    EXPECT_EQ(merged.continuation(kDistance, 0, 2).n, forward.continuation(kDistance, 0, 2).n);
}

// A scripted camera sample: a contribution and an unguided decision before any point, a distance-stage
// point (weight 0.5) split in two, the original making a guided direction decision and reaching a
// direction-stage point (weight 0.25), each branch making an unguided decision. Each copy is one
// sample of its point; subtrees include their children and their decisions (the cost unit); a
// decision's S is its subtree's contributions; the root counts everything.
TEST(CellStatistics, RecorderCreditsEachCopyWithItsSubtree) {
    CellStatistics stats(3);  // leaves 0, 1 and "outside"
    PixelMoments pixels(2, 1);
    CellRecorder rec(stats, pixels);
    const DecisionRecord unguided;  // no guided mixture
    rec.begin(1, 2.f);
    rec.record_contribution(Color3(0.2f));
    rec.record_decision(DecisionKind::Distance, unguided);
    rec.record_continuation(kDistance, 0, Vec3f(1, 0, 0), 0.f, Color3(0.5f));
    const int copy = rec.branch_point();
    rec.record_decision(DecisionKind::Direction, DecisionRecord{true, 0, 1.f, 1.f, 1.f});
    rec.record_contribution(Color3(0.3f));
    rec.record_continuation(kDirection, 0, Vec3f(0, 1, 0), 0.f, Color3(0.25f));
    rec.record_decision(DecisionKind::Surface, unguided);
    rec.record_contribution(Color3(0.1f));
    rec.resume_branch(copy);
    rec.record_decision(DecisionKind::Distance, unguided);
    rec.record_contribution(Color3(0.4f));
    rec.end_camera_sample(2);
    rec.end();

    const ContinuationMoments& d = stats.continuation(kDistance, 0, 0);
    ASSERT_EQ(d.n, 2u);  // the original (0.3 + 0.1) / 0.5 and the copy 0.4 / 0.5
    EXPECT_NEAR(d.sum.value(), 1.6, 1e-6);
    EXPECT_NEAR(d.sum_sq.value(), 1.28, 1e-6);
    EXPECT_EQ(d.cost, 3u);  // 2 decisions in the original's subtree, 1 in the copy's
    const ContinuationMoments& w = stats.continuation(kDirection, 0, 2);
    ASSERT_EQ(w.n, 1u);
    EXPECT_NEAR(w.sum.value(), 0.4, 1e-6);
    EXPECT_EQ(w.cost, 1u);
    // The guided direction decision: S = 0.3 + 0.1 over I = 2, at the share it was sampled with.
    const DecisionMoments& m = stats.decision(DecisionKind::Direction, 0);
    ASSERT_EQ(m.count, 1u);
    EXPECT_NEAR(m.current.value(), 0.04, 1e-6);
    EXPECT_EQ(stats.camera_samples(), 1u);
    EXPECT_EQ(stats.cost(), 4u);
    EXPECT_EQ(stats.unrecorded_decisions(), 3u);
    EXPECT_EQ(stats.branches(), 2u);
    EXPECT_NEAR(stats.camera_moment(), 0.25, 1e-6);  // (1.0 / 2)^2
    // The pixel's sample: X / I = 1.0 / 2; a leaf outside the field goes to the last cell.
    const PixelMoments::Pixel px = pixels.at(1);
    EXPECT_EQ(px.n, 1.0);
    EXPECT_NEAR(px.sum, 0.5, 1e-4);
    EXPECT_EQ(pixels.at(0).n, 0.0);
    rec.begin(-1, 1.f);
    rec.record_continuation(kDistance, -1, Vec3f(0, 0, -1), 0.f, Color3(1.f));
    rec.record_contribution(Color3(1.f));
    rec.end();
    EXPECT_EQ(stats.continuation(kDistance, 2, 5).n, 1u);
}

// The pilot's path (no splitting): each guided decision's S is everything contributed after it.
TEST(CellStatistics, DecisionsOfAChainSeeWhatFollowed) {
    CellStatistics stats(2);
    PixelMoments pixels(1, 1);
    CellRecorder rec(stats, pixels);
    rec.begin(0, 1.f);
    rec.record_contribution(Color3(1.f));  // before every decision: no decision's
    rec.record_decision(DecisionKind::Distance, DecisionRecord{true, 0, 2.f, 1.f, 3.f});
    rec.record_contribution(Color3(0.5f));
    rec.record_decision(DecisionKind::Direction, DecisionRecord{true, 1, 1.f, 1.f, 1.f});
    rec.record_contribution(Color3(0.25f));
    rec.end();
    const DecisionMoments& first = stats.decision(DecisionKind::Distance, 0);
    const DecisionMoments& second = stats.decision(DecisionKind::Direction, 1);
    EXPECT_NEAR(first.current.value(), 0.75 * 0.75, 1e-6);
    EXPECT_NEAR(second.current.value(), 0.25 * 0.25, 1e-6);
    // Share 0 (the unguided density alone): s2 q_cur / p_u; share 0.5: s2 q_cur / ((p_u + p_g) / 2).
    EXPECT_NEAR(first.m[0].value(), 0.5625 * 2.0, 1e-6);
    EXPECT_NEAR(first.m[3].value(), 0.5625 * 2.0 / 2.0, 1e-6);
    EXPECT_NEAR(stats.camera_moment(), 1.75 * 1.75, 1e-6);
}

TEST(CellStatistics, PixelOfFilmPosition) {
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
ContinuationSnapshot known_snapshot(const EarsSettings& settings, CellStatistics& stats) {
    PixelMoments pixels(1, 1);
    for (int i = 0; i < 64; ++i) {
        stats.add_continuation(kDistance, 0, 1, (i % 2) ? 2.0 : 0.0, 4);
        stats.add_camera_sample(1.0, 8, 0, 1);
        pixels.add(0, (i % 2) ? 2.0 : 0.0);
    }
    return ContinuationSnapshot::from(stats, pixels, settings, 8.0);
}

}  // namespace

TEST(CellStatistics, FactorFromKnownMoments) {
    EarsSettings settings;
    settings.min_samples = 32;
    CellStatistics stats(2);
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
    CellStatistics few(2);
    EXPECT_LT(known_snapshot(settings, few).factor(kDistance, 0, 1, 1.f), 0.f);
    // Nothing learned at all.
    EXPECT_LT(ContinuationSnapshot().factor(kDistance, 0, 1, 1.f), 0.f);
}

// The learned pixel estimate: the pixel's mean x shrunk towards 1 by the prior samples.
TEST(CellStatistics, LearnedPixelEstimate) {
    EarsSettings settings;
    settings.pixel_prior = 4.0;
    PixelMoments pixels(2, 1);
    for (int i = 0; i < 12; ++i) pixels.add(0, 3.0);  // the field's I is 3x too dark here
    CellStatistics stats(1);
    const ContinuationSnapshot snap = ContinuationSnapshot::from(stats, pixels, settings, 0.0);
    EXPECT_NEAR(snap.pixel_estimate(0, 2.f), 2.f * (4.f + 36.f) / (4.f + 12.f), 1e-4f);
    EXPECT_FLOAT_EQ(snap.pixel_estimate(1, 2.f), 2.f);   // no samples: I
    EXPECT_FLOAT_EQ(snap.pixel_estimate(-1, 2.f), 2.f);  // outside the film: I
}

// The adaptive budget: budget_factor x C_0 over the measured cost per branch, within
// [min_budget, max_branches]; a fixed budget replaces it.
TEST(CellStatistics, BranchBudgetFromMeasuredCost) {
    EarsSettings settings;
    settings.budget_factor = 8.f;
    settings.min_budget = 4.f;
    settings.max_branches = 64;
    CellStatistics stats(1);
    PixelMoments pixels(1, 1);
    for (int i = 0; i < 10; ++i) stats.add_camera_sample(1.0, 12, 0, 3);  // 4 decisions per branch
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 6.0).branch_budget(), 12.f);
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 1.0).branch_budget(), 4.f);
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 100.0).branch_budget(), 64.f);
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 0.0).branch_budget(), 4.f);  // C_0 unknown
    settings.fixed_budget = 3.f;
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 6.0).branch_budget(), 3.f);
}
