// Focused photon emission (integrators/guided/training/emission_focus.h): the warped emission sample times its
// weight integrates any function of the uniform sample exactly (unbiased photons), useful cells
// get most of the samples, unknown cells (no pilot photon) stay useful, and an emitter that
// reached nothing (or everything) stays uniform with weight 1.
#include <gtest/gtest.h>

#include <cmath>

#include "volguide/core/sampler.h"
#include "volguide/integrators/guided/training/emission_focus.h"

using namespace volguide;

namespace {

constexpr int R = EmissionPilot::kResolution;

Point2f cell_center(int x, int y) { return Point2f((float(x) + 0.5f) / R, (float(y) + 0.5f) / R); }

// A pilot in which every cell of emitter 0 saw photons, and only a 3x3 window deposited.
EmissionPilot window_pilot() {
    EmissionPilot pilot(2);
    for (int y = 0; y < R; ++y)
        for (int x = 0; x < R; ++x) {
            const bool in_window = x >= 20 && x < 23 && y >= 40 && y < 43;
            pilot.record(0, cell_center(x, y), in_window);
            pilot.record(0, cell_center(x, y), false);
        }
    return pilot;  // emitter 1: no pilot photon at all
}

}  // namespace

TEST(EmissionFocus, WarpedSamplesTimesWeightIntegrateAnyFunction) {
    const EmissionFocus focus(window_pilot(), 0.02f);
    ASSERT_TRUE(focus.active());
    // f: smooth over the square plus a bump in the window; exact integral by midpoint sums.
    auto f = [](Point2f u) {
        const float bump = std::exp(-((u.x - 0.33f) * (u.x - 0.33f) + (u.y - 0.64f) * (u.y - 0.64f)) * 400.f);
        return 0.2f + u.x * u.y + 5.f * bump;
    };
    double exact = 0;
    const int M = 1024;
    for (int j = 0; j < M; ++j)
        for (int i = 0; i < M; ++i) exact += f(Point2f((i + 0.5f) / M, (j + 0.5f) / M));
    exact /= double(M) * M;
    const int N = 2000000;
    double sum = 0, sum2 = 0;
    int in_window = 0;
    for (int i = 0; i < N; ++i) {
        Sampler s(9, 0, uint64_t(i));
        const float uc = s.next_1d();
        Point2f u = s.next_2d();
        const float w = focus.warp(0, uc, u);
        ASSERT_GE(u.x, 0.f);
        ASSERT_LT(u.x, 1.f);
        ASSERT_GE(u.y, 0.f);
        ASSERT_LT(u.y, 1.f);
        const double v = double(w) * f(u);
        sum += v;
        sum2 += v * v;
        const int cx = int(u.x * R), cy = int(u.y * R);
        in_window += cx >= 19 && cx < 24 && cy >= 39 && cy < 44;  // the window dilated by one cell
    }
    const double mean = sum / N, se = std::sqrt((sum2 / N - mean * mean) / N);
    EXPECT_LT(std::abs(mean - exact), 4.0 * se) << "mean " << mean << " exact " << exact << " se " << se;
    EXPECT_GT(double(in_window) / N, 0.97) << "the useful cells (dilated window) get 1 - defensive";
    EXPECT_NEAR(focus.useful_fraction(0), 0.98f + 0.02f * 25.f / float(R * R), 1e-5f);
}

TEST(EmissionFocus, UnknownCellsStayUseful) {
    EmissionPilot pilot(1);
    // Only the left half of the square saw pilot photons, none deposited: the right half is unknown.
    for (int y = 0; y < R; ++y)
        for (int x = 0; x < R / 2; ++x) pilot.record(0, cell_center(x, y), false);
    const EmissionFocus focus(pilot, 0.02f);
    int right = 0;
    const int N = 100000;
    for (int i = 0; i < N; ++i) {
        Sampler s(2, 0, uint64_t(i));
        Point2f u = s.next_2d();
        focus.warp(0, s.next_1d(), u);
        right += u.x >= float(R / 2 - 1) / R;  // the unknown half, dilated by one column
    }
    EXPECT_GT(double(right) / N, 0.97);
}

TEST(EmissionFocus, NothingOrEverythingUsefulStaysUniform) {
    EmissionPilot pilot(3);
    for (int y = 0; y < R; ++y)
        for (int x = 0; x < R; ++x) {
            pilot.record(0, cell_center(x, y), false);  // emitter 0 reaches no medium
            pilot.record(1, cell_center(x, y), true);   // emitter 1 reaches media everywhere
        }
    // emitter 2 had no pilot photon (all unknown)
    const EmissionFocus focus(pilot, 0.02f);
    for (size_t e = 0; e < 3; ++e) {
        Point2f u(0.3f, 0.7f);
        EXPECT_EQ(focus.warp(e, 0.5f, u), 1.f) << "emitter " << e;
        EXPECT_EQ(u, Point2f(0.3f, 0.7f));
    }
    // Without a pilot the focus is inactive.
    EXPECT_FALSE(EmissionFocus().active());
}
