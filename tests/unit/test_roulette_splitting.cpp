// Guided Russian roulette and splitting (docs/theory.md §9.2, §9.4): the weight-window factor (eq. 9.1),
// stochastic rounding (E[n] = q, so n copies of weight 1/q estimate 1), the clamps, the branch cap
// and the invalid-estimate guard, and the branch statistics.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "support/running_stats.h"
#include "volguide/core/sampler.h"
#include "volguide/guiding/roulette_splitting.h"

using namespace volguide;
using namespace volguide::test;

TEST(RouletteSplitting, WindowOfOneIsThePapersRatio) {
    for (float r : {0.01f, 0.2f, 0.999f, 1.f, 1.7f, 13.f}) EXPECT_FLOAT_EQ(weight_window_factor(r, 1.f), r);
}

TEST(RouletteSplitting, WindowOfFiveIsAdrrs) {
    // s = 5: RR below 1/3 towards 1/3, nothing in [1/3, 5/3], splitting above towards 5/3.
    EXPECT_FLOAT_EQ(weight_window_factor(0.1f, 5.f), 0.3f);
    EXPECT_FLOAT_EQ(weight_window_factor(0.3f, 5.f), 0.9f);
    EXPECT_FLOAT_EQ(weight_window_factor(0.34f, 5.f), 1.f);
    EXPECT_FLOAT_EQ(weight_window_factor(1.6f, 5.f), 1.f);
    EXPECT_FLOAT_EQ(weight_window_factor(5.f, 5.f), 3.f);
    // Continuous at both bounds.
    EXPECT_NEAR(weight_window_factor(1.f / 3.f - 1e-6f, 5.f), 1.f, 1e-5f);
    EXPECT_NEAR(weight_window_factor(5.f / 3.f + 1e-6f, 5.f), 1.f, 1e-5f);
}

TEST(RouletteSplitting, StochasticRoundingHasMeanQAndWeightOneOverQ) {
    for (float q : {0.1f, 0.37f, 1.f, 2.5f, 7.93f}) {
        RunningStats n_stats, estimate;
        for (int i = 0; i < 200000; ++i) {
            Sampler s(5, 0, uint64_t(i));
            const int n = stochastic_round(q, s.next_1d());
            ASSERT_GE(n, int(std::floor(q)));
            ASSERT_LE(n, int(std::floor(q)) + 1);
            n_stats.add(n);
            estimate.add(double(n) * (1.0 / q));  // n copies of a unit-valued path, each weighted 1/q
        }
        SCOPED_TRACE(q);
        EXPECT_LT(n_stats.z(q, 1e-9), 4.0) << n_stats.mean();
        EXPECT_LT(estimate.z(1.0, 1e-9), 4.0) << estimate.mean();
    }
    // Integral q: exactly q copies.
    for (float u : {0.f, 0.5f, 0.9999f}) EXPECT_EQ(stochastic_round(3.f, u), 3);
}

TEST(RouletteSplitting, FactorClampsAndGuards) {
    RouletteSplittingSettings s;
    s.mode = RouletteMode::GuidedSplitting;
    s.window = 1.f;
    s.q_min = 0.1f;
    s.q_max = 20.f;
    s.max_branches = 64;
    const RouletteSplitting grrs(s);
    // E[X] = <w * Psi> = 0.5 against I = 0.25: q = 2.
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(0.5f), 0.25f, 1), 2.f);
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(1e-4f), 1.f, 1), 0.1f);  // q_min
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(1e3f), 1.f, 1), 20.f);   // q_max
    // Channel averages: <(1, 0, 0) * (3, 3, 3)> = 1.
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f, 0.f, 0.f), Color3(3.f), 1.f, 1), 1.f);
    // No usable estimate: no decision.
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(0.f), 1.f, 1), 1.f);
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(NAN), 1.f, 1), 1.f);
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(1.f), 0.f, 1), 1.f);
    // The branch cap: with 60 of 64 branches made, at most 5 continuations (this one and 4 new).
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(10.f), 1.f, 60), 5.f);
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(10.f), 1.f, 64), 1.f);
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(0.5f), 1.f, 64), 0.5f);  // RR still allowed at the cap
    const RouletteSplittingStats st = grrs.stats();
    EXPECT_EQ(st.decisions, 10u);
    EXPECT_EQ(st.invalid_estimates, 3u);
    EXPECT_EQ(st.cap_limited, 2u);

    // The branch budget: q <= floor(allowance), RR untouched; adaptive when branch_budget = 0 (issue 55:
    // kDefaultBudget until the pilot has measured the costs; AdaptiveBudgetWithinTheCeiling).
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(10.f), 1.f, 1, 3.7f), 3.f);
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(10.f), 1.f, 1, 1.5f), 1.f);
    EXPECT_FLOAT_EQ(grrs.factor(Color3(1.f), Color3(0.5f), 1.f, 1, 1.f), 0.5f);
    EXPECT_EQ(grrs.stats().budget_limited, 2u);
    EXPECT_EQ(grrs.initial_allowance(), RouletteSplitting::kDefaultBudget);
    RouletteSplittingSettings budgeted = s;
    budgeted.branch_budget = 16.f;
    EXPECT_FLOAT_EQ(RouletteSplitting(budgeted).initial_allowance(), 16.f);

    // grr: Russian roulette only.
    s.mode = RouletteMode::Guided;
    const RouletteSplitting grr(s);
    EXPECT_FLOAT_EQ(grr.factor(Color3(1.f), Color3(4.f), 1.f, 1), 1.f);
    EXPECT_FLOAT_EQ(grr.factor(Color3(1.f), Color3(0.25f), 1.f, 1), 0.25f);
}

TEST(RouletteSplitting, BranchStatistics) {
    RouletteSplittingSettings s;
    s.mode = RouletteMode::GuidedSplitting;
    s.max_branches = 8;
    const RouletteSplitting rs(s);
    for (int i = 0; i < 997; ++i) rs.count_camera_sample(1);
    rs.count_camera_sample(3);
    rs.count_camera_sample(8);
    rs.count_camera_sample(8);
    rs.count_outcome(0);
    rs.count_outcome(1);
    rs.count_outcome(4);
    const RouletteSplittingStats st = rs.stats();
    EXPECT_EQ(st.camera_samples, 1000u);
    EXPECT_EQ(st.kills, 1u);
    EXPECT_EQ(st.splits, 1u);
    EXPECT_EQ(st.extra_branches, 3u);
    EXPECT_EQ(st.branches_quantile(0.5), 1);
    EXPECT_EQ(st.branches_quantile(0.998), 3);
    EXPECT_EQ(st.branches_quantile(0.999), 8);
    std::map<std::string, double> named;
    for (const auto& [k, v] : st.named()) named[k] = v;
    EXPECT_NEAR(named.at("rrs_branches_per_camera_sample"), (997.0 + 3 + 16) / 1000.0, 1e-12);
    EXPECT_EQ(named.at("rrs_branches_max"), 8.0);
}

// Issue 55: a camera sample's branches are bounded by its cost. The ceiling is 16 whatever the budget;
// the adaptive budget is kBudgetFactor x C_0 / c (the pilot's counted costs), within [kMinBudget, 16],
// kDefaultBudget before it is measured; a fixed rrs_branch_budget replaces it, below the ceiling.
TEST(RouletteSplitting, AdaptiveBudgetWithinTheCeiling) {
    RouletteSplittingSettings s;
    s.mode = RouletteMode::GuidedSplitting;
    EXPECT_EQ(s.max_branches, 16);
    RouletteSplitting rs(s);
    EXPECT_EQ(rs.initial_allowance(), RouletteSplitting::kDefaultBudget);
    rs.set_cost_ratio(1.6f);  // floor(2 x 1.6)
    EXPECT_EQ(rs.initial_allowance(), 3.f);
    rs.set_cost_ratio(0.3f);  // long heavy-tailed paths: at least two branches
    EXPECT_EQ(rs.initial_allowance(), RouletteSplitting::kMinBudget);
    rs.set_cost_ratio(40.f);  // never above the ceiling
    EXPECT_EQ(rs.initial_allowance(), 16.f);
    rs.set_cost_ratio(0.f);  // not measured
    EXPECT_EQ(rs.initial_allowance(), RouletteSplitting::kDefaultBudget);
    rs.set_cost_ratio(std::numeric_limits<float>::quiet_NaN());
    EXPECT_EQ(rs.initial_allowance(), RouletteSplitting::kDefaultBudget);
    s.branch_budget = 100.f;  // a fixed budget stays under the ceiling
    EXPECT_EQ(RouletteSplitting(s).initial_allowance(), 16.f);
    s.branch_budget = 5.f;
    RouletteSplitting fixed(s);
    fixed.set_cost_ratio(1.f);
    EXPECT_EQ(fixed.initial_allowance(), 5.f);
    // A split never makes more copies than the allowance: q <= floor(allowance).
    EXPECT_LE(fixed.bound(50.f, 1, fixed.initial_allowance()), 5.f);
    std::map<std::string, double> named;
    for (const auto& [k, v] : fixed.stats().named()) named[k] = v;
    EXPECT_EQ(named.at("rrs_branch_budget"), 5.0);
}
