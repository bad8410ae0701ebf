// The learner's cell statistics and recorder (integrators/guided/estimates/cell_statistics.h,
// cell_recorder.h) and rrs=ears's snapshot of them (continuation_snapshot.h; docs/theory.md §9.8): the
// direction bins, the moments against known integrals, exact sums in any order, the recorder's
// split-tree bookkeeping on a scripted camera sample (continuations, decisions, their costs from the
// cost model's counted work), the statistics' bytes, the factor and the branch budget from known moments.
#include <gtest/gtest.h>

#include <cmath>

#include "volguide/core/sampler.h"
#include "volguide/integrators/guided/estimates/cell_recorder.h"
#include "volguide/integrators/guided/estimates/continuation_snapshot.h"

using namespace volguide;

namespace {

constexpr ContinuationStage kDistance = ContinuationStage::Distance;
constexpr ContinuationStage kDirection = ContinuationStage::Direction;

// Every unit costs 1: a decision whose record holds one segment costs 1.
const CostModel kUnitCosts = [] {
    std::array<double, kWorkUnits> ones;
    ones.fill(1.0);
    return CostModel(ones);
}();

DecisionRecord record(bool mixture, int leaf, float pdf, float p_u, float p_g) {
    DecisionRecord r{mixture, leaf, pdf, p_u, p_g};
    r.own.add(Work::Segment);
    return r;
}

// A continuation point decided with factor q (guided), in `leaf`.
Continuation decided(int leaf, float q) {
    Continuation c;
    c.leaf = leaf;
    c.q = q;
    c.guided = true;
    c.q_guided = q;
    return c;
}

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
        stats.add_continuation(kDirection, 1, 4, double(s.next_1d()), 3.0);
    }
    const ContinuationMoments& m = stats.continuation(kDirection, 1, 4);
    ASSERT_EQ(m.n, uint64_t(n));
    EXPECT_NEAR(m.sum.value() / n, 0.5, 4.0 * std::sqrt(1.0 / 12.0 / n));
    EXPECT_NEAR(m.sum_sq.value() / n, 1.0 / 3.0, 4.0 * std::sqrt(4.0 / 45.0 / n));
    EXPECT_EQ(m.cost.value(), 3.0 * n);
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
    for (double y : ys) forward.add_continuation(kDistance, 0, 2, y, 1.0);
    for (size_t i = ys.size(); i-- > 0;) (i % 3 ? a : b).add_continuation(kDistance, 0, 2, ys[i], 1.0);
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
// sample of its point; subtrees include their children and their decisions' costs (1 each); a
// decision's S is its subtree's contributions; the root counts everything.
TEST(CellStatistics, RecorderCreditsEachCopyWithItsSubtree) {
    CellStatistics stats(3);  // leaves 0, 1 and "outside"
    PixelMoments pixels(2, 1);
    CellRecorder rec(stats, pixels, kUnitCosts);
    const DecisionRecord unguided = record(false, -1, 0.f, 0.f, 0.f);  // no guide could make it
    rec.begin(1, 2.f);
    rec.record_contribution(Color3(0.2f));
    rec.record_decision(DecisionKind::Distance, unguided);
    rec.record_continuation(kDistance, decided(0, 1.f), Vec3f(1, 0, 0), Color3(0.5f));
    const int copy = rec.branch_point();
    rec.record_decision(DecisionKind::Direction, record(true, 0, 1.f, 1.f, 1.f));
    rec.record_contribution(Color3(0.3f));
    rec.record_continuation(kDirection, decided(0, 1.f), Vec3f(0, 1, 0), Color3(0.25f));
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
    EXPECT_NEAR(d.cost.value(), 3.0, 1e-9);  // 2 decisions in the original's subtree, 1 in the copy's
    const ContinuationMoments& w = stats.continuation(kDirection, 0, 2);
    ASSERT_EQ(w.n, 1u);
    EXPECT_NEAR(w.sum.value(), 0.4, 1e-6);
    EXPECT_NEAR(w.cost.value(), 1.0, 1e-9);
    // The guided direction decision: S = 0.3 + 0.1 over I = 2, at the share it was sampled with; its own
    // cost 1 and 1 after it (the surface decision).
    const DecisionMoments& m = stats.decision(DecisionKind::Direction, 0);
    ASSERT_EQ(m.count, 1u);
    EXPECT_NEAR(m.current.value(), 0.04, 1e-6);
    EXPECT_NEAR(m.own.value(), 1.0, 1e-9);
    EXPECT_NEAR(m.current_after.value(), 1.0, 1e-9);
    // Decisions no guide could make are not statistics of their cells, only costs.
    EXPECT_EQ(stats.decision(DecisionKind::Distance, 2).count + stats.decision(DecisionKind::Distance, 2).unguided, 0u);
    EXPECT_EQ(stats.camera_samples(), 1u);
    EXPECT_NEAR(stats.cost(), 4.0, 1e-9);
    EXPECT_EQ(stats.branches(), 2u);
    EXPECT_NEAR(stats.camera_moment(), 0.25, 1e-6);  // (1.0 / 2)^2
    // The split point: two copies of 0.8 each (E[Y^2] = 0.64, E[Y]^2 from their product 0.64), its weight
    // before the decision 0.5 / I = 0.25: the second moment at q = 1 is 0.25^2 x 0.64.
    const ContinuationChoiceMoments& p = stats.continuation_choice(0);
    EXPECT_NEAR(p.known_points.value(), 2.0, 1e-9);  // the split point and the direction point
    EXPECT_NEAR(p.current_m.value(), 0.0625 * 0.64 + 0.125 * 0.125 * 0.16, 1e-6);
    // The pixel's sample: X / I = 1.0 / 2; a leaf outside the field goes to the last cell.
    const PixelMoments::Pixel px = pixels.at(1);
    EXPECT_EQ(px.n, 1.0);
    EXPECT_NEAR(px.sum, 0.5, 1e-4);
    EXPECT_EQ(pixels.at(0).n, 0.0);
    rec.begin(-1, 1.f);
    rec.record_continuation(kDistance, decided(-1, 1.f), Vec3f(0, 0, -1), Color3(1.f));
    rec.record_contribution(Color3(1.f));
    rec.end();
    EXPECT_EQ(stats.continuation(kDistance, 2, 5).n, 1u);
}

// An unsplit path: each guided decision's S is everything contributed after it, and what followed it
// cost, reweighted to every share.
TEST(CellStatistics, DecisionsOfAChainSeeWhatFollowed) {
    CellStatistics stats(2);
    PixelMoments pixels(1, 1);
    CellRecorder rec(stats, pixels, kUnitCosts);
    rec.begin(0, 1.f);
    rec.record_contribution(Color3(1.f));  // before every decision: no decision's
    rec.record_decision(DecisionKind::Distance, record(true, 0, 2.f, 1.f, 3.f));
    rec.record_contribution(Color3(0.5f));
    rec.record_decision(DecisionKind::Direction, record(true, 1, 1.f, 1.f, 1.f));
    rec.record_contribution(Color3(0.25f));
    rec.end();
    const DecisionMoments& first = stats.decision(DecisionKind::Distance, 0);
    const DecisionMoments& second = stats.decision(DecisionKind::Direction, 1);
    EXPECT_NEAR(first.current.value(), 0.75 * 0.75, 1e-6);
    EXPECT_NEAR(second.current.value(), 0.25 * 0.25, 1e-6);
    // Share 0 (the unguided density alone): s2 q_cur / p_u; share 0.5: s2 q_cur / ((p_u + p_g) / 2).
    EXPECT_NEAR(first.m[0].value(), 0.5625 * 2.0, 1e-6);
    EXPECT_NEAR(first.m[3].value(), 0.5625 * 2.0 / 2.0, 1e-6);
    // What followed the first decision (the second's cost, 1) under share a: 1 x q_a / q_cur.
    EXPECT_NEAR(first.after[0].value(), 1.0 * 1.0 / 2.0, 1e-6);
    EXPECT_NEAR(first.after[3].value(), 1.0 * 2.0 / 2.0, 1e-6);
    EXPECT_NEAR(stats.camera_moment(), 1.75 * 1.75, 1e-6);
}

// A decision the allocation made unguided (share 0: guidable, no mixture) and a point that made no
// decision (the walk's roulette of survival 0.5 followed, its 1/0.5 in what the copy collected).
TEST(CellStatistics, UnguidedDecisionsAndTheWalksRoulette) {
    CellStatistics stats(2);
    PixelMoments pixels(1, 1);
    CellRecorder rec(stats, pixels, kUnitCosts);
    rec.begin(0, 1.f);
    DecisionRecord off = record(false, 0, 0.f, 0.f, 0.f);
    off.guidable = true;
    rec.record_decision(DecisionKind::Distance, off);
    Continuation none;  // no decision
    none.leaf = 0;
    none.q_unguided = 0.5f;
    rec.record_continuation(kDirection, none, Vec3f(1, 0, 0), Color3(1.f));
    rec.record_contribution(Color3(2.f));  // a survivor of the roulette: 2 x 1 collected
    rec.end();
    const DecisionMoments& m = stats.decision(DecisionKind::Distance, 0);
    EXPECT_EQ(m.count, 0u);
    EXPECT_EQ(m.unguided, 1u);
    EXPECT_NEAR(m.unguided_m.value(), 4.0, 1e-6);
    EXPECT_NEAR(m.unguided_own.value(), 1.0, 1e-9);
    const ContinuationChoiceMoments& p = stats.continuation_choice(0);
    EXPECT_NEAR(p.other_points.value(), 1.0, 1e-9);
    // E[Y^2] = 0.5 x 2^2 = 2; under the walk's roulette (q = 0.5) the second moment is 2 / 0.5 = 4: what was observed.
    EXPECT_NEAR(p.other_m.value(), 4.0, 1e-6);
    EXPECT_NEAR(p.known_points.value(), 0.0, 1e-12);
}

// Stochastic-rounded splitting: E[n (n - 1)] = f (2 q - f - 1), f = floor(q); roulette: b^2 a2 / q.
TEST(CellStatistics, ContinuationSecondMomentOfAFactor) {
    EXPECT_NEAR(continuation_second_moment(1.0, 2.0, 1.0, 0.5), 4.0, 1e-12);
    EXPECT_NEAR(continuation_second_moment(1.0, 2.0, 1.0, 1.0), 2.0, 1e-12);
    EXPECT_NEAR(continuation_second_moment(1.0, 2.0, 1.0, 2.0), (2.0 * 2.0 + 2.0 * 1.0) / 4.0, 1e-12);
    // q = 2.5: n is 2 or 3 equally, E[n (n - 1)] = (2 + 6) / 2 = 4.
    EXPECT_NEAR(continuation_second_moment(0.5, 2.0, 1.0, 2.5), 0.25 * (2.0 / 2.5 + 4.0 / 6.25), 1e-12);
}

// The statistics' bytes give the same sums back; a cut or altered record is refused.
TEST(CellStatistics, BytesRoundTripExactly) {
    CellStatistics stats(3);
    PixelMoments pixels(1, 1);
    CellRecorder rec(stats, pixels, kUnitCosts);
    rec.begin(0, 0.7f);
    rec.record_decision(DecisionKind::Direction, record(true, 1, 0.3f, 0.2f, 0.9f));
    rec.record_continuation(kDistance, decided(1, 2.5f), Vec3f(0, 1, 0), Color3(0.3f));
    rec.branch_point();
    rec.record_contribution(Color3(0.123f));
    rec.end();
    const std::string bytes = stats.serialize();
    const CellStatistics back = CellStatistics::deserialize(bytes);
    EXPECT_EQ(back.serialize(), bytes);
    EXPECT_EQ(back.cells(), 3u);
    EXPECT_EQ(back.decision(DecisionKind::Direction, 1).m[2].value(), stats.decision(DecisionKind::Direction, 1).m[2].value());
    EXPECT_THROW(CellStatistics::deserialize(bytes.substr(0, bytes.size() - 3)), std::runtime_error);
    EXPECT_THROW(CellStatistics::deserialize(bytes + "x"), std::runtime_error);
    std::string wrong = bytes;
    wrong[0] ^= 1;
    EXPECT_THROW(CellStatistics::deserialize(wrong), std::runtime_error);
}

// A control sample (the unguided walk's) adds only its value and cost, apart from the allocation's
// camera samples, and its value to the pixel's moments; the sums survive the bytes.
TEST(CellStatistics, ControlSamplesAreKeptApartAndRoundTrip) {
    CellStatistics stats(2);
    PixelMoments pixels(1, 1);
    CellRecorder rec(stats, pixels, kUnitCosts);
    rec.begin(0, 0.5f, true);
    rec.record_decision(DecisionKind::Direction, record(true, 0, 0.3f, 0.2f, 0.9f));
    rec.record_contribution(Color3(1.f));
    rec.end();
    EXPECT_EQ(stats.control_samples(), 1u);
    EXPECT_EQ(stats.camera_samples(), 0u);
    EXPECT_DOUBLE_EQ(stats.control_moment(), 4.0);  // (1 / 0.5)^2
    EXPECT_GT(stats.control_cost(), 0.0);
    EXPECT_EQ(stats.decision(DecisionKind::Direction, 0).count, 0u);
    EXPECT_EQ(pixels.at(0).n, 1.0);
    const CellStatistics back = CellStatistics::deserialize(stats.serialize());
    EXPECT_EQ(back.control_samples(), 1u);
    EXPECT_EQ(back.control_moment(), stats.control_moment());
    EXPECT_EQ(back.control_cost(), stats.control_cost());
}

// mean_square: over the samples, each pixel's unbiased squared mean ((sum^2 - sum of squares) / (n (n-1)));
// pixels of one sample are left out. The bytes and += keep every sum.
TEST(CellStatistics, PixelMeanSquareSerializeAndAdd) {
    PixelMoments a(2, 1);
    for (double x : {1.0, 3.0}) a.add(0, x);  // pixel 0: (16 - 10) / 2 = 3 for each of 2 samples
    a.add(1, 5.0);                            // one sample: left out
    EXPECT_NEAR(a.mean_square(), 3.0, 1e-6);
    PixelMoments b(2, 1);
    b.restore(a.serialize());
    EXPECT_EQ(b.serialize(), a.serialize());
    // pixel 0: 4 samples, n mu^2 = (64 - 20) / 3; pixel 1: 2 samples, (100 - 50) / 1; over 6 samples
    b += a;
    EXPECT_NEAR(b.mean_square(), (44.0 / 3.0 + 50.0) / 6.0, 1e-5);
    EXPECT_THROW(b.restore(a.serialize().substr(0, 9)), std::runtime_error);
    PixelMoments other(3, 1);
    EXPECT_THROW(other.restore(a.serialize()), std::runtime_error);
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
        stats.add_continuation(kDistance, 0, 1, (i % 2) ? 2.0 : 0.0, 4.0);
        stats.add_camera_sample(1.0, 8.0, 1);
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
    for (int i = 0; i < 10; ++i) stats.add_camera_sample(1.0, 12.0, 3);  // a cost of 4 per branch
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 6.0).branch_budget(), 12.f);
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 1.0).branch_budget(), 4.f);
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 100.0).branch_budget(), 64.f);
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 0.0).branch_budget(), 4.f);  // C_0 unknown
    settings.fixed_budget = 3.f;
    EXPECT_FLOAT_EQ(ContinuationSnapshot::from(stats, pixels, settings, 6.0).branch_budget(), 3.f);
}
