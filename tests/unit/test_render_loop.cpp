// The render loop without a scene: pass schedule, bit-identical images for any thread count,
// seeds, dropped non-finite samples, cancellation (a partial pass is discarded), time budgets,
// unbiased means and per-sample variances.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <numeric>

#include "volguide/integrators/render_loop.h"
#include "volguide/render/sensors/rfilters.h"

namespace volguide {
namespace {

bool bit_identical(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Color3)) == 0;
}

// A noisy, position-dependent test signal that uses a few sampler dimensions.
Color3 noisy(Point2f uv, Sampler& s) {
    float a = s.next_1d(), b = s.next_1d();
    return Color3(uv.x + a, uv.y * b, std::sin(10.f * uv.x) + a * b);
}

TEST(RenderLoop, PassSchedule) {
    EXPECT_EQ(pass_schedule(1), std::vector<int>({1}));
    EXPECT_EQ(pass_schedule(10), std::vector<int>({1, 1, 2, 4, 2}));
    EXPECT_EQ(pass_schedule(0), std::vector<int>());
    for (int spp : {1, 7, 64, 100, 1000}) {
        auto s = pass_schedule(spp);
        EXPECT_EQ(std::accumulate(s.begin(), s.end(), 0), spp);
        // Every schedule is a prefix of the unbounded one, except its truncated last pass.
        for (size_t k = 0; k + 1 < s.size(); ++k) EXPECT_EQ(s[k], pass_size(int(k)));
        EXPECT_LE(s.back(), pass_size(int(s.size()) - 1));
        for (int v : s) EXPECT_LE(v, 8);
    }
}

TEST(RenderLoop, BitIdenticalForAnyThreadCount) {
    GaussianFilter gaussian;
    TentFilter tent(1.f);
    for (const ReconstructionFilter* f : {static_cast<const ReconstructionFilter*>(&gaussian),
                                          static_cast<const ReconstructionFilter*>(&tent)}) {
        for (bool border : {false, true}) {
            FrameSetup setup{37, 21, f, border, 4, 5, true};
            RenderOptions opt;
            opt.spp = 11;
            opt.tile_size = 8;
            opt.threads = 1;
            RenderResult one = render_frame(setup, noisy, opt);
            opt.threads = 2;
            RenderResult two = render_frame(setup, noisy, opt);
            opt.threads = 3;
            RenderResult three = render_frame(setup, noisy, opt);
            EXPECT_EQ(one.spp, 11);
            EXPECT_EQ(one.stats.passes, 5);
            EXPECT_TRUE(bit_identical(one.mean, two.mean));
            EXPECT_TRUE(bit_identical(one.mean, three.mean));
            EXPECT_TRUE(bit_identical(one.variance, two.variance));
            EXPECT_TRUE(bit_identical(one.variance, three.variance));
            EXPECT_EQ(one.stats.threads, 1);
            EXPECT_EQ(two.stats.threads, 2);
        }
    }
}

TEST(RenderLoop, OnPassSeesEveryMergedPassInOrder) {
    BoxFilter box;
    FrameSetup setup{9, 7, &box, false, 4, 5, false};
    RenderOptions opt;
    opt.spp = 10;
    std::vector<int> spps;
    std::vector<double> times;
    Image last;
    opt.on_pass = [&](int spp, double seconds, const Image& mean) {
        spps.push_back(spp);
        times.push_back(seconds);
        last = mean;
    };
    RenderResult r = render_frame(setup, noisy, opt);
    EXPECT_EQ(spps, std::vector<int>({1, 2, 4, 8, 10}));  // cumulative pass_schedule(10)
    for (size_t k = 1; k < times.size(); ++k) EXPECT_GE(times[k], times[k - 1]);
    EXPECT_GE(times.front(), 0.0);
    EXPECT_TRUE(bit_identical(last, r.mean));  // the last snapshot is the final image
}

TEST(RenderLoop, SeedsAndDefaults) {
    BoxFilter box;
    FrameSetup setup{9, 7, &box, false, 3, 42, false};
    RenderOptions opt;
    RenderResult def = render_frame(setup, noisy, opt);
    EXPECT_EQ(def.spp, 3);  // the sensor's sample count
    EXPECT_EQ(def.stats.seed, 42u);
    EXPECT_EQ(def.stats.samples, 9u * 7u * 3u);
    EXPECT_TRUE(def.variance.pixels.empty());
    opt.seed = 42;
    EXPECT_TRUE(bit_identical(def.mean, render_frame(setup, noisy, opt).mean));
    opt.seed = 43;
    EXPECT_FALSE(bit_identical(def.mean, render_frame(setup, noisy, opt).mean));
}

TEST(RenderLoop, NonFiniteSamplesAreCountedAndDropped) {
    BoxFilter box;
    FrameSetup setup{8, 8, &box, false, 16, 1, true};
    RadianceFn sometimes_nan = [](Point2f uv, Sampler& s) {
        float a = s.next_1d();
        if (a < 0.1f) return Color3(std::nanf(""), 0.f, 0.f);
        if (a > 0.95f) return Color3(0.f, Infinity, 0.f);
        return Color3(1.f);
    };
    RenderResult r = render_frame(setup, sometimes_nan, RenderOptions{});
    EXPECT_GT(r.stats.nonfinite_samples, 0u);
    EXPECT_LT(r.stats.nonfinite_samples, r.stats.samples);
    // The replay location really produces a non-finite value.
    ASSERT_TRUE(r.stats.first_nonfinite.has_value());
    const SampleLocation& at = *r.stats.first_nonfinite;
    Sampler replay(1, uint64_t(at.y) * 8 + uint64_t(at.x), uint64_t(at.sample));
    Vec2f u = replay.next_2d();
    EXPECT_FALSE(sometimes_nan(Point2f((at.x + u.x) / 8.f, (at.y + u.y) / 8.f), replay).is_finite());
    for (const Color3& c : r.mean.pixels) {
        EXPECT_TRUE(c.is_finite());
        EXPECT_TRUE(c == Color3(1.f) || c == Color3(0.f));
    }
    for (const Color3& c : r.variance.pixels) EXPECT_TRUE(c.is_finite());
}

TEST(RenderLoop, CancelledPassIsDiscarded) {
    GaussianFilter g;
    FrameSetup setup{20, 12, &g, false, 4, 3, true};
    std::atomic<bool> cancel{false};
    std::atomic<int> calls{0};
    const int per_pass = 20 * 12;
    // Passes 1, 1, 2, 4: cancel in the middle of the fourth pass (spp 4..8).
    RadianceFn cancelling = [&](Point2f uv, Sampler& s) {
        if (calls.fetch_add(1) == 4 * per_pass + 100) cancel = true;
        return noisy(uv, s);
    };
    RenderOptions opt;
    opt.spp = 64;
    opt.threads = 2;
    opt.cancel = &cancel;
    RenderResult r = render_frame(setup, cancelling, opt);
    EXPECT_TRUE(r.stats.cancelled);
    EXPECT_EQ(r.spp, 4);
    EXPECT_EQ(r.stats.samples, uint64_t(4 * per_pass));
    // The image equals a 4-spp render: nothing of the interrupted pass leaked in.
    RenderOptions four;
    four.spp = 4;
    RenderResult ref = render_frame(setup, noisy, four);
    EXPECT_TRUE(bit_identical(r.mean, ref.mean));
    EXPECT_TRUE(bit_identical(r.variance, ref.variance));

    // Cancelled before anything: zero spp, and the caller knows.
    cancel = true;
    RenderResult none = render_frame(setup, noisy, opt);
    EXPECT_EQ(none.spp, 0);
    EXPECT_TRUE(none.stats.cancelled);
}

TEST(RenderLoop, TimeBudgetAlwaysCompletesTheFirstPass) {
    BoxFilter box;
    FrameSetup setup{6, 6, &box, false, 4, 0, false};
    RenderOptions opt;
    opt.time_budget = 1e-9;  // already spent when rendering starts
    RenderResult r = render_frame(setup, noisy, opt);
    EXPECT_EQ(r.spp, 1);
    EXPECT_TRUE(r.stats.time_limited);
    RenderOptions one;
    one.spp = 1;
    EXPECT_TRUE(bit_identical(r.mean, render_frame(setup, noisy, one).mean));
}

TEST(RenderLoop, ProgressReportsReachTheTarget) {
    BoxFilter box;
    FrameSetup setup{16, 16, &box, false, 4, 0, false};
    RenderOptions opt;
    opt.spp = 6;
    std::vector<Progress> reports;
    opt.progress = [&](const Progress& p) { reports.push_back(p); };
    render_frame(setup, noisy, opt);
    ASSERT_FALSE(reports.empty());
    EXPECT_EQ(reports.back().spp_done, 6);
    EXPECT_EQ(reports.back().spp_target, 6);
    EXPECT_DOUBLE_EQ(reports.back().fraction, 1.0);
    for (size_t k = 1; k < reports.size(); ++k) EXPECT_GE(reports[k].spp_done, reports[k - 1].spp_done);
}

TEST(RenderLoop, MeanAndPerSampleVariance) {
    // Radiance = u ~ U[0,1) independent of position: mean 1/2, per-sample variance 1/12.
    BoxFilter box;
    FrameSetup setup{8, 8, &box, false, 256, 7, true};
    RenderResult r = render_frame(
        setup, [](Point2f, Sampler& s) { return Color3(s.next_1d()); }, RenderOptions{});
    double mean = 0, var = 0;
    for (size_t p = 0; p < r.mean.pixels.size(); ++p) {
        mean += r.mean.pixels[p].r;
        var += r.variance.pixels[p].g;
    }
    mean /= 64;
    var /= 64;
    EXPECT_NEAR(mean, 0.5, 0.01);
    EXPECT_NEAR(var, 1.0 / 12.0, 0.004);

    // A horizontal ramp through a Gaussian filter: interior pixels are unbiased at their centre.
    GaussianFilter g;
    FrameSetup ramp{24, 4, &g, true, 64, 7, false};
    RenderResult rr = render_frame(
        ramp, [](Point2f uv, Sampler&) { return Color3(uv.x); }, RenderOptions{});
    for (int x = 0; x < 24; ++x) EXPECT_NEAR(rr.mean.at(x, 2).r, (x + 0.5f) / 24.f, 4e-3f) << x;
}

// PassReport::relative_variance (issue 39): per pixel the unbiased variance of the pass's samples'
// luminance over (m^2 + 0.01), m the pixel's mean when the first pass of two samples was merged, averaged
// over the film. A signal 1 + a (u - 1/2), u uniform, has variance a^2 / 12 and mean 1 in every pixel
// (a small a keeps the noise of m negligible); a constant one has none; passes of one sample per pixel
// have no estimate (NaN). The same value for one and two threads (tile-order sums).
TEST(RenderLoop, PassReportsThePerSampleNoise) {
    BoxFilter box;
    FrameSetup setup{24, 16, &box, false, 4, 5, false};
    const float a = 0.2f;
    auto uniform = [&](Point2f, Sampler& s) { return Color3(1.f + a * (s.next_1d() - 0.5f)); };  // luminance = value
    std::vector<PassReport> passes;
    RenderOptions opt;
    opt.spp = 36;  // passes of 1, 1, 2, 4, 8, 8, 8, 4
    opt.end_pass = [&](const PassReport& p) { passes.push_back(p); };
    render_frame(setup, uniform, opt);
    ASSERT_EQ(passes.size(), 8u);
    // Passes of one sample, and the first of two (it fixes the normaliser), report none.
    for (int k : {0, 1, 2}) EXPECT_TRUE(std::isnan(passes[size_t(k)].relative_variance)) << k;
    EXPECT_FALSE(std::isnan(passes[3].relative_variance));
    const double expected = (a * a / 12.0) / (1.0 + 0.01);
    double mean8 = 0;
    for (int k : {4, 5, 6}) {
        EXPECT_EQ(passes[size_t(k)].spp, 8);
        mean8 += passes[size_t(k)].relative_variance / 3;
    }
    // 384 pixels x 3 passes: the mean's relative standard error is ~1 %; a biased (divide by n)
    // variance would read 12.5 % low.
    EXPECT_NEAR(mean8, expected, 0.05 * expected);
    EXPECT_EQ(passes.back().spp_done, 36);
    EXPECT_EQ(passes.back().spp, 4);
    for (const PassReport& p : passes) EXPECT_GE(p.pass_seconds, 0.0);

    std::vector<PassReport> constant;
    opt.end_pass = [&](const PassReport& p) { constant.push_back(p); };
    render_frame(setup, [](Point2f, Sampler&) { return Color3(0.7f); }, opt);
    EXPECT_EQ(constant[4].relative_variance, 0.0);

    std::vector<double> one, two;
    for (auto [threads, out] : {std::pair{1, &one}, std::pair{2, &two}}) {
        opt.threads = threads;
        opt.end_pass = [out = out](const PassReport& p) { out->push_back(p.relative_variance); };
        render_frame(setup, noisy, opt);
    }
    ASSERT_EQ(one.size(), two.size());
    for (size_t k = 3; k < one.size(); ++k) EXPECT_EQ(one[k], two[k]) << k;
}

}  // namespace
}  // namespace volguide
