// The allocation (integrators/guided/estimates/allocation.h): the fit from known statistics, the
// shrinkage toward the kd parent, the continuation's rule, exploration, the bytes.
//  - a one-dimensional decision with known densities: unguided p_u = 1 on [0, 1), guided p_g = 2 on
//    [0, 1/2); samples drawn (stratified) from the mixture q = (p_u + p_g) / 2. Where the integrand
//    lives on [0, 1/2) (the guide is right) M(a) = 2 / (1 + a); where it lives on [1/2, 1) (the guide
//    is wrong) M(a) = 2 / (1 - a). With a guided decision costing little more than the unguided one
//    the right cell is guided and the wrong one is not; a guided decision that costs far more than
//    what it saves is not guided anywhere.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "volguide/integrators/guided/estimates/allocation.h"

using namespace volguide;

namespace {

// Two leaves under one root (cells 0 and 1) and the cell outside the field (2).
SpatialTree two_leaves() {
    std::vector<SpatialTree::Node> nodes(3);
    nodes[0].axis = 0;
    nodes[0].split = 0.5f;
    nodes[0].child = 1;
    nodes[1].child = 0;  // leaves: axis 3
    nodes[2].child = 1;
    return SpatialTree::from_nodes(BBox3f(Point3f(0.f), Point3f(1.f)), nodes);
}

// Sample i of n from q = 1.5 on [0, 1/2), 0.5 on [1/2, 1) (stratified inversion).
float mixture_sample(int i, int n) {
    const float u = (float(i) + 0.5f) / float(n);
    return u < 0.75f ? u / 1.5f : 0.5f + (u - 0.75f) / 0.5f;
}

// n direction decisions of `cell` whose integrand is 2 on [lo, lo + 1/2) (S = f / q, I = 1), each
// costing `guided` (and `unguided` had it been unguided), followed by work of cost 1; one camera sample
// per decision.
void add_toy(CellStatistics& stats, size_t cell, float lo, int n, double guided, double unguided = 0.0) {
    for (int i = 0; i < n; ++i) {
        const float x = mixture_sample(i, n);
        const float p_u = 1.f, p_g = x < 0.5f ? 2.f : 0.f, q = 0.5f * (p_u + p_g);
        const float f = (x >= lo && x < lo + 0.5f) ? 2.f : 0.f;
        DecisionSample d;
        d.cell = cell;
        d.s2 = double(f) * double(f) / (double(q) * double(q));
        d.mixture = true;
        d.q_cur = q;
        d.p_u = p_u;
        d.p_g = p_g;
        d.own = guided;
        d.own_unguided = unguided;
        d.after = 1.0;
        stats.add_decision(DecisionKind::Direction, d);
        stats.add_camera_sample(d.s2, 2.0 + guided, 1);
    }
}

AllocationSettings no_exploration() {
    AllocationSettings s;
    s.explore_min = 0.f;
    s.explore_target = 0.0;
    return s;
}

}  // namespace

TEST(Allocation, GuidesWhereTheGuideIsRightAndNotWhereItIsWrong) {
    CellStatistics stats(3);
    add_toy(stats, 0, 0.f, 4000, 0.1);
    add_toy(stats, 1, 0.5f, 4000, 0.1);
    const Allocation a = Allocation::fit(stats, two_leaves(), no_exploration());
    EXPECT_GT(a.table()[0].share[size_t(DecisionKind::Direction)], 0.5f);
    EXPECT_EQ(a.table()[1].share[size_t(DecisionKind::Direction)], 0.f);
    EXPECT_GT(a.gain(), 1.0);
    EXPECT_NEAR(a.summary().guided[size_t(DecisionKind::Direction)], 0.5, 1e-9);  // one cell of two
    EXPECT_FALSE(a.off());
}

TEST(Allocation, ADecisionThatCostsMoreThanItSavesIsNotGuided) {
    CellStatistics stats(3);
    add_toy(stats, 0, 0.f, 4000, 50.0);  // the guide halves M but makes the sample ~50x dearer
    const Allocation a = Allocation::fit(stats, two_leaves(), no_exploration());
    EXPECT_EQ(a.table()[0].share[size_t(DecisionKind::Direction)], 0.f);
    EXPECT_NEAR(a.gain(), 1.0, 1e-9);
}

// A cell with few samples follows its parent's estimate: here the sibling's evidence that the guide
// is right, against its own few samples saying it is wrong.
TEST(Allocation, AFewSamplesFollowTheParent) {
    CellStatistics stats(3);
    add_toy(stats, 0, 0.f, 8000, 0.1);
    add_toy(stats, 1, 0.5f, 8, 0.1);
    AllocationSettings settings = no_exploration();
    settings.prior = 256.0;
    EXPECT_GT(Allocation::fit(stats, two_leaves(), settings).table()[1].share[size_t(DecisionKind::Direction)], 0.f);
    settings.prior = 0.0;  // its own samples alone
    EXPECT_EQ(Allocation::fit(stats, two_leaves(), settings).table()[1].share[size_t(DecisionKind::Direction)], 0.f);
}

// Continuation points whose copies vary (E[Y^2] = 4 E[Y]^2): splitting into 4 divides their second
// moment by ~4 for 4x the copies' cost; where the copies cost little it pays, where they cost much
// (against what else the camera sample costs) it does not, and roulette of a dim path saves cost.
TEST(Allocation, TheContinuationRuleFollowsSecondMomentAndCost) {
    for (const double copy_cost : {0.01, 100.0}) {
        CellStatistics stats(3);
        for (int i = 0; i < 1000; ++i) {
            ContinuationSample s;
            s.cell = 0;
            s.b = 1.0;
            s.q_cur = 4.f;
            s.q_unguided = 1.f;
            s.q_guided = 4.f;
            s.guided_known = true;
            s.a2 = 4.0;
            s.b2 = 1.0;
            s.copy_cost = copy_cost;
            stats.add_continuation_point(s);
            stats.add_camera_sample(4.0, 1.0 + 4.0 * copy_cost, 4);
        }
        const Allocation a = Allocation::fit(stats, two_leaves(), no_exploration());
        if (copy_cost < 1.0)
            EXPECT_EQ(a.table()[0].rule, ContinuationRule::Splitting);
        else
            EXPECT_EQ(a.table()[0].rule, ContinuationRule::Unguided);
    }
}

TEST(Allocation, ExplorationFallsWithTheDecisionsSeenAndOnlyRecordedSamplesExplore) {
    CellStatistics stats(3);
    add_toy(stats, 1, 0.5f, 4000, 0.1);  // not guided: explores
    AllocationSettings settings;
    settings.explore_target = 400.0;
    settings.explore_min = 0.01f;
    const Allocation a = Allocation::fit(stats, two_leaves(), settings);
    const Allocation::Cell& c = a.table()[1];
    ASSERT_EQ(c.share[size_t(DecisionKind::Direction)], 0.f);
    EXPECT_FLOAT_EQ(c.explore[size_t(DecisionKind::Direction)], 0.1f);  // 400 / 4000
    EXPECT_FLOAT_EQ(a.table()[2].explore[size_t(DecisionKind::Direction)], 1.f);  // nothing seen
    EXPECT_EQ(a.share(DecisionKind::Direction, 1, 0.05f, true), Allocation::kConfigured);
    EXPECT_EQ(a.share(DecisionKind::Direction, 1, 0.05f, false), 0.f);
    EXPECT_EQ(a.share(DecisionKind::Direction, 1, 0.5f, true), 0.f);
    EXPECT_EQ(a.share(DecisionKind::Direction, 7, 0.5f, true), Allocation::kConfigured);  // beyond the table
    // The first pass explores everything; the unguided allocation nothing.
    EXPECT_EQ(Allocation::exploring(3).share(DecisionKind::Distance, 0, 0.99f, true), Allocation::kConfigured);
    EXPECT_TRUE(Allocation::unguided(3).off());
    EXPECT_EQ(Allocation::unguided(3).share(DecisionKind::Distance, 0, 0.f, true), 0.f);
    EXPECT_FALSE(Allocation::exploring(3).off());
}

TEST(Allocation, ExplorationCoinIsUniformAndAFunctionOfWhereTheDecisionIs) {
    const int n = 20000;
    int below = 0;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const float c = exploration_coin(Point3f(0.001f * float(i), 0.5f, 0.25f), Vec3f(0, 0, 1), 2);
        ASSERT_GE(c, 0.f);
        ASSERT_LT(c, 1.f);
        below += c < 0.1f;
        sum += c;
    }
    EXPECT_NEAR(double(below) / n, 0.1, 4.0 * std::sqrt(0.09 / n));
    EXPECT_NEAR(sum / n, 0.5, 4.0 * std::sqrt(1.0 / 12.0 / n));
    const Point3f p(0.3f, 0.2f, 0.1f);
    EXPECT_EQ(exploration_coin(p, Vec3f(1, 0, 0), 1), exploration_coin(p, Vec3f(1, 0, 0), 1));
    EXPECT_NE(exploration_coin(p, Vec3f(1, 0, 0), 1), exploration_coin(p, Vec3f(1, 0, 0), 2));
}

TEST(Allocation, BytesRoundTripAndMalformedBytesAreRefused) {
    CellStatistics stats(3);
    add_toy(stats, 0, 0.f, 2000, 0.1);
    const Allocation a = Allocation::fit(stats, two_leaves(), AllocationSettings{});
    const std::string bytes = a.serialize();
    const Allocation b = Allocation::deserialize(bytes);
    EXPECT_EQ(b.serialize(), bytes);
    EXPECT_EQ(b.cells(), 3u);
    EXPECT_EQ(b.table()[0].share, a.table()[0].share);
    EXPECT_THROW(Allocation::deserialize(bytes.substr(0, bytes.size() - 1)), std::runtime_error);
    EXPECT_THROW(Allocation::deserialize(bytes + "z"), std::runtime_error);
    std::string bad = bytes;
    const char nan_bits[4] = {0x00, 0x00, char(0xc0), 0x7f};  // the first cell's first share: NaN
    for (int k = 0; k < 4; ++k) bad[size_t(16 + k)] = nan_bits[k];
    EXPECT_THROW(Allocation::deserialize(bad), std::runtime_error);
    EXPECT_THROW(Allocation::deserialize(""), std::runtime_error);
}
