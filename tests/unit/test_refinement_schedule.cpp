// RefinementSchedule (issue 39, docs/theory.md §22.4): when guided_volpath refines its field during
// the render, judged by each refinement's stretch of passes against the stretch before it.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>

#include "volguide/integrators/guided/training/refinement_schedule.h"

namespace volguide {
namespace {

PassReport schedule_pass(int spp_done, int spp, double seconds, double pass_seconds, double noise) {
    PassReport p;
    p.spp_done = spp_done;
    p.spp = spp;
    p.seconds = seconds;
    p.pass_seconds = pass_seconds;
    p.relative_variance = noise;
    return p;
}

std::map<std::string, double> schedule_stats(const RefinementSchedule& s) {
    std::map<std::string, double> out;
    for (const auto& [k, v] : s.named()) out[k] = v;
    return out;
}

constexpr double kNoNoise = std::numeric_limits<double>::quiet_NaN();

// Without a budget: the first refinement at first_spp once a pass measured the noise, the next at the
// doubling while the last one paid by at least `gain`; then it stops and stays stopped.
TEST(RefinementSchedule, RefinesAtDoublingsWhileItPays) {
    RefinementScheduleSettings settings;
    settings.passes = 5;
    settings.first_spp = 4;
    settings.gain = 0.05;
    RefinementSchedule s(settings, 0.0, 1.0);
    EXPECT_EQ(s.on_pass(schedule_pass(1, 1, 0, 0, kNoNoise)), RefinementAction::Continue);
    EXPECT_EQ(s.on_pass(schedule_pass(2, 1, 0, 0, kNoNoise)), RefinementAction::Continue);
    EXPECT_EQ(s.on_pass(schedule_pass(4, 2, 0, 0, 1.0)), RefinementAction::Refine);
    s.done(0.5);
    EXPECT_EQ(s.on_pass(schedule_pass(8, 4, 0, 0, 0.8)), RefinementAction::Refine);  // 0.8x: paid
    s.done(0.5);
    EXPECT_EQ(s.on_pass(schedule_pass(16, 8, 0, 0, 0.79)), RefinementAction::Continue);  // 0.99x: not enough
    EXPECT_EQ(s.on_pass(schedule_pass(32, 8, 0, 0, 0.1)), RefinementAction::Continue);   // stopped for good
    EXPECT_EQ(s.refinements(), 2);
    const auto st = schedule_stats(s);
    EXPECT_EQ(st.at("refine_passes"), 2.0);
    EXPECT_EQ(st.at("refine_stop_reason"), double(int(RefinementStop::NoGain)));
    EXPECT_EQ(st.at("refine_stop_spp"), 16.0);
    EXPECT_DOUBLE_EQ(st.at("refine_seconds"), 1.0);
    EXPECT_EQ(st.at("refine_stretch0_spp"), 4.0);
    EXPECT_DOUBLE_EQ(st.at("refine_stretch1_inefficiency"), 0.8);
}

// A stretch's noise is the passes' noise weighted by their samples; a refinement that made it worse is
// undone (Revert), once.
TEST(RefinementSchedule, UndoesARefinementThatMadeItWorse) {
    RefinementScheduleSettings settings;
    settings.passes = 5;
    settings.first_spp = 4;
    RefinementSchedule s(settings, 0.0, 1.0);
    s.on_pass(schedule_pass(2, 2, 0, 0, 2.0));
    EXPECT_EQ(s.on_pass(schedule_pass(4, 2, 0, 0, 1.0)), RefinementAction::Refine);  // stretch 1.5
    s.done(0.1);
    EXPECT_EQ(s.on_pass(schedule_pass(6, 2, 0, 0, 1.0)), RefinementAction::Continue);  // before the doubling
    EXPECT_EQ(s.on_pass(schedule_pass(8, 2, 0, 0, 2.5)), RefinementAction::Revert);    // 1.75 > 1.5
    s.done(0.1);
    EXPECT_EQ(s.refinements(), 1);
    EXPECT_EQ(s.on_pass(schedule_pass(16, 8, 0, 0, 0.1)), RefinementAction::Continue);
    EXPECT_EQ(schedule_stats(s).at("refine_stop_reason"), double(int(RefinementStop::Worse)));
}

// "Worse" needs more than twice the ratio's standard error (from the passes' relative_variance_error):
// a stretch 10 % worse with 10 % errors only stops refining.
TEST(RefinementSchedule, UndoesOnlyWhatIsSignificantlyWorse) {
    RefinementScheduleSettings settings;
    settings.passes = 5;
    settings.first_spp = 4;
    RefinementSchedule s(settings, 0.0, 1.0);
    PassReport p = schedule_pass(4, 4, 0, 0, 1.0);
    p.relative_variance_error = 0.1;
    EXPECT_EQ(s.on_pass(p), RefinementAction::Refine);
    s.done(0.1);
    p = schedule_pass(8, 4, 0, 0, 1.1);
    p.relative_variance_error = 0.11;
    EXPECT_EQ(s.on_pass(p), RefinementAction::Continue);
    EXPECT_EQ(schedule_stats(s).at("refine_stop_reason"), double(int(RefinementStop::NoGain)));
}

TEST(RefinementSchedule, StopsAtThePassLimitAndIsOffWithoutPasses) {
    RefinementScheduleSettings settings;
    settings.passes = 1;
    settings.first_spp = 2;
    RefinementSchedule s(settings, 0.0, 1.0);
    EXPECT_EQ(s.on_pass(schedule_pass(2, 2, 0, 0, 1.0)), RefinementAction::Refine);
    s.done(0.1);
    EXPECT_EQ(s.on_pass(schedule_pass(4, 2, 0, 0, 0.5)), RefinementAction::Continue);
    EXPECT_EQ(schedule_stats(s).at("refine_stop_reason"), double(int(RefinementStop::PassLimit)));

    settings.passes = 0;
    RefinementSchedule off(settings, 0.0, 1.0);
    for (int spp = 2; spp < 64; spp *= 2) EXPECT_EQ(off.on_pass(schedule_pass(spp, spp / 2, 0, 0, 1.0)), RefinementAction::Continue);
    EXPECT_EQ(off.refinements(), 0);
}

// With a time budget the inefficiency is noise x seconds per spp: a refinement that lowers the noise
// but slows the samples more is worse. The first refinement needs the budget to cover four times the
// training; a later one needs the remaining time x the last gain to cover twice its cost.
TEST(RefinementSchedule, TimeBudgetWeighsSecondsAndCosts) {
    RefinementScheduleSettings settings;
    settings.passes = 5;
    settings.first_spp = 4;
    {
        RefinementSchedule s(settings, 60.0, 5.0);
        EXPECT_EQ(s.on_pass(schedule_pass(4, 4, 45.0, 4.0, 1.0)), RefinementAction::Continue);  // 15 s < 20 s left
        EXPECT_EQ(schedule_stats(s).at("refine_stop_reason"), double(int(RefinementStop::Budget)));
    }
    {
        RefinementSchedule s(settings, 60.0, 5.0);
        EXPECT_EQ(s.on_pass(schedule_pass(4, 4, 10.0, 4.0, 1.0)), RefinementAction::Refine);  // 1 x 1 s/spp
        s.done(2.0);
        // Noise 0.7x, but 1.5 s per spp: inefficiency 1.05 > 1.
        EXPECT_EQ(s.on_pass(schedule_pass(8, 4, 18.0, 6.0, 0.7)), RefinementAction::Revert);
    }
    {
        RefinementSchedule s(settings, 60.0, 5.0);
        EXPECT_EQ(s.on_pass(schedule_pass(4, 4, 10.0, 4.0, 1.0)), RefinementAction::Refine);
        s.done(8.0);
        // 0.9x paid, but 60 - 50 = 10 s left x 0.1 = 1 s < 2 x 8 s.
        EXPECT_EQ(s.on_pass(schedule_pass(8, 4, 50.0, 4.0, 0.9)), RefinementAction::Continue);
        EXPECT_EQ(schedule_stats(s).at("refine_stop_reason"), double(int(RefinementStop::Budget)));
    }
}

}  // namespace
}  // namespace volguide
