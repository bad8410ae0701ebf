// Guided product distance sampling on a 1-D analytic ray (docs/theory.md §14.7): exact estimates give a
// zero-variance estimator of L(0); noisy (log-normal) estimates with defensive mixing, clamping and
// the filter stay unbiased (z-tests, grey and chromatic); sampled distances follow the pdf (chi-square).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "support/analytic_ray.h"
#include "support/chi2.h"
#include "support/running_stats.h"
#include "volguide/core/sampler.h"
#include "volguide/guiding/guided_distance.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// Log-normal factors exp(sigma * N(0,1)), fixed per bin and quantity: a "cache" that is wrong by a
// factor of ~2 but deterministic along the ray.
std::function<float(size_t, int)> lognormal_noise(uint32_t seed, float sigma) {
    auto table = std::make_shared<std::vector<float>>();
    std::mt19937 rng(seed);
    std::normal_distribution<float> n(0.f, 1.f);
    for (int i = 0; i < 64; ++i) table->push_back(std::exp(sigma * n(rng)));
    return [table](size_t k, int which) { return (*table)[2 * k + size_t(which)]; };
}

enum class Kind { Incremental, Tabulated };

DistanceSample draw(Kind kind, const std::vector<DistanceBin>& bins, const TabulatedDistance& tab,
                    const GuidedDistanceSettings& s, Sampler& rng) {
    if (kind == Kind::Tabulated) return tab.sample(rng);
    AnalyticRay::Source src{&bins};
    return sample_incremental_distance(src, rng, s);
}

}  // namespace

TEST(GuidedDistanceZeroVariance, ExactEstimatesGiveZeroVariance) {
    const AnalyticRay ray = six_bin_ray();
    const auto bins = ray.bins();
    const double L0 = ray.L0_average();
    // c_T = 0, no clamp; the filter is exact for exact estimates, so it may be on or off.
    for (float A : {1.f, 0.5f})
        for (Kind kind : {Kind::Incremental, Kind::Tabulated}) {
            const GuidedDistanceSettings s = settings(0.f, 1.f, A);
            const TabulatedDistance tab(bins, ray.L_surface.average(), s);
            RunningStats stats;
            int medium = 0;
            for (uint64_t i = 0; i < 20000; ++i) {
                Sampler rng(11, 0, i);
                const DistanceSample d = draw(kind, bins, tab, s, rng);
                medium += d.event == DistanceEvent::Medium;
                stats.add(ray.estimate_average(d));
            }
            const double rel_std = std::sqrt(stats.variance()) / L0;
            std::printf(
                "exact estimates, %s, A = %.2f: mean / L(0) - 1 = %.2e, relative std %.2e, %d%% medium\n",
                kind == Kind::Incremental ? "incremental" : "tabulated", A, stats.mean() / L0 - 1.0, rel_std,
                medium / 200);
            EXPECT_LT(rel_std, 1e-5) << "A " << A << " kind " << int(kind);
            EXPECT_NEAR(stats.mean() / L0, 1.0, 1e-5);
            EXPECT_GT(medium, 1000);  // both events occur
            EXPECT_LT(medium, 19000);
        }
}

TEST(GuidedDistanceZeroVariance, VreDenominatorIsNearZeroVarianceWithExactEstimates) {
    // The Vre denominator N + T L~ reads the radiance beyond a bin as the lookup at its start: exact
    // to first order in the bin's optical depth, so with exact estimates it is close to, but not,
    // zero-variance (six_bin_ray's bins have optical depths 0.1-1.2). Unbiased all the same.
    const AnalyticRay ray = six_bin_ray();
    const auto bins = ray.bins();
    const double L0 = ray.L0_average();
    const GuidedDistanceSettings s = settings(0.f, 1.f, 1.f, DistanceDenominator::Vre);
    RunningStats stats, transmittance;
    for (uint64_t i = 0; i < 100000; ++i) {
        Sampler rng(12, 0, i);
        AnalyticRay::Source src{&bins};
        stats.add(ray.estimate_average(sample_incremental_distance(src, rng, s)));
        Sampler rng_t(13, 0, i);
        AnalyticRay::Source src_t{&bins};
        transmittance.add(
            ray.estimate_average(sample_incremental_distance(src_t, rng_t, settings(1.f, 1.f, 1.f))));
    }
    const double rel_std = std::sqrt(stats.variance()) / L0,
                 rel_std_t = std::sqrt(transmittance.variance()) / L0;
    std::printf("exact estimates, vre denominator: relative std %.3f (transmittance sampling %.3f), z %.2f\n",
                rel_std, rel_std_t, stats.z(L0));
    EXPECT_LT(stats.z(L0), 3.0);
    EXPECT_GT(rel_std, 1e-5);              // not zero-variance...
    EXPECT_LT(rel_std, 0.25 * rel_std_t);  // ...but far closer to it than free flight
}

TEST(GuidedDistanceZeroVariance, TransmittanceSamplingAloneIsNotZeroVariance) {
    // Power check: the same estimator with c_T = 1 (free flight) has a clearly non-zero variance.
    const AnalyticRay ray = six_bin_ray();
    const auto bins = ray.bins();
    const GuidedDistanceSettings s = settings(1.f, 1.f, 1.f);
    RunningStats stats;
    for (uint64_t i = 0; i < 20000; ++i) {
        Sampler rng(11, 0, i);
        AnalyticRay::Source src{&bins};
        stats.add(ray.estimate_average(sample_incremental_distance(src, rng, s)));
    }
    EXPECT_GT(std::sqrt(stats.variance()) / ray.L0_average(), 0.1);
    EXPECT_LT(stats.z(ray.L0_average()), 3.0);
}

TEST(GuidedDistanceZeroVariance, NoisyEstimatesAreUnbiased) {
    const int N = 100000;
    for (bool chromatic : {false, true}) {
        const AnalyticRay ray = six_bin_ray(chromatic);
        const auto L = ray.incident_at_starts();
        const auto noise = lognormal_noise(chromatic ? 5 : 4, 0.7f);
        const auto bins = ray.bins(noise);
        struct Case {
            float A;
            Kind kind;
            DistanceDenominator den;
        };
        for (const Case cs : {Case{0.5f, Kind::Incremental, DistanceDenominator::Incident},
                              Case{1.f, Kind::Incremental, DistanceDenominator::Incident},
                              Case{0.5f, Kind::Incremental, DistanceDenominator::Vre},
                              Case{0.5f, Kind::Tabulated, DistanceDenominator::Incident},
                              Case{1.f, Kind::Tabulated, DistanceDenominator::Incident}}) {
            const float A = cs.A;
            const Kind kind = cs.kind;
            // A throughput-like channel split for the chromatic ray (the renderer's choice).
            const GuidedDistanceSettings s =
                settings(0.5f, 0.9f, A, cs.den, chromatic ? Color3(0.5f, 0.3f, 0.2f) : Color3(1.f / 3.f));
            const TabulatedDistance tab(bins, std::nullopt, s);  // surface mass extrapolated
            RunningStats per_channel[3];
            for (uint64_t i = 0; i < uint64_t(N); ++i) {
                Sampler rng(21, chromatic, i);
                const DistanceSample d = draw(kind, bins, tab, s, rng);
                for (int c = 0; c < 3; ++c) per_channel[c].add(ray.estimate(d, c));
            }
            std::printf("noisy, %s, %s%s, A = %.2f: z per channel %.2f %.2f %.2f, relative std %.2f\n",
                        chromatic ? "chromatic" : "grey",
                        kind == Kind::Incremental ? "incremental" : "tabulated",
                        cs.den == DistanceDenominator::Vre ? " (vre)" : "", A, per_channel[0].z(L[0][0]),
                        per_channel[1].z(L[0][1]), per_channel[2].z(L[0][2]),
                        std::sqrt(per_channel[1].variance()) / L[0][1]);
            for (int c = 0; c < 3; ++c)
                EXPECT_LT(per_channel[c].z(L[0][size_t(c)]), 3.0)
                    << "chromatic " << chromatic << " A " << A << " kind " << int(kind) << " vre "
                    << (cs.den == DistanceDenominator::Vre) << " channel " << c << ": mean "
                    << per_channel[c].mean() << " expected " << L[0][size_t(c)] << " +- "
                    << per_channel[c].std_error();
        }
    }
}

TEST(GuidedDistanceZeroVariance, WrongPdfIsDetectedAsBiased) {
    // Power check of the z-test above: weighting filtered decisions with the unfiltered pdf is biased.
    const AnalyticRay ray = six_bin_ray();
    const auto bins = ray.bins(lognormal_noise(4, 0.7f));
    const GuidedDistanceSettings sampled = settings(0.5f, 0.9f, 0.25f), wrong = settings(0.5f, 0.9f, 1.f);
    RunningStats stats;
    for (uint64_t i = 0; i < 100000; ++i) {
        Sampler rng(21, 0, i);
        AnalyticRay::Source src{&bins};
        DistanceSample d = sample_incremental_distance(src, rng, sampled);
        d.pdf = d.event == DistanceEvent::Medium ? incremental_distance_pdf(bins, d.t, wrong)
                                                 : incremental_surface_probability(bins, wrong);
        stats.add(ray.estimate_average(d));
    }
    EXPECT_GT(stats.z(ray.L0_average()), 5.0) << stats.mean() << " vs " << ray.L0_average();
}

TEST(GuidedDistanceZeroVariance, SampledDistancesFollowThePdf) {
    struct Case {
        bool chromatic;
        float c_T, A;
        Kind kind;
        DistanceDenominator den = DistanceDenominator::Incident;
    };
    const Case cases[] = {{false, 0.5f, 0.5f, Kind::Incremental},
                          {true, 0.5f, 0.5f, Kind::Incremental},
                          {true, 0.5f, 1.f, Kind::Incremental},
                          {false, 0.f, 0.5f, Kind::Incremental},
                          {false, 0.5f, 0.5f, Kind::Tabulated},
                          {true, 0.5f, 1.f, Kind::Tabulated},
                          {true, 0.5f, 0.5f, Kind::Incremental, DistanceDenominator::Vre},
                          {false, 0.f, 1.f, Kind::Incremental, DistanceDenominator::Vre}};
    for (const Case& cs : cases) {
        const AnalyticRay ray = six_bin_ray(cs.chromatic);
        const auto bins = ray.bins(lognormal_noise(9, 0.7f));
        const GuidedDistanceSettings s =
            settings(cs.c_T, 0.9f, cs.A, cs.den, cs.chromatic ? Color3(0.6f, 0.3f, 0.1f) : Color3(1.f / 3.f));
        const TabulatedDistance tab(bins, std::nullopt, s);
        ChiSquareOptions opt;
        opt.sample_count = 200000;
        opt.rows = 1;
        opt.cols = 72;  // 0.05 wide: the bin boundaries of six_bin_ray fall on cell edges
        opt.test_count = int(std::size(cases));
        opt.weight_check_count = 0;
        uint64_t index = 0;
        const auto r = chi2_test_plane(
            [&](Sampler&) {
                Sampler rng(31, 0, index++);
                const DistanceSample d = draw(cs.kind, bins, tab, s, rng);
                ChiSquareSample out;
                out.d = Vec3f(d.t, 0.5f, 0.f);
                out.valid = d.event == DistanceEvent::Medium;  // the surface is the rest bin
                return out;
            },
            [&](const Vec3f& p) {
                return double(cs.kind == Kind::Tabulated ? tab.pdf(p.x)
                                                         : incremental_distance_pdf(bins, p.x, s));
            },
            Rect2{0.0, 0.0, ray.end(), 1.0}, opt);
        EXPECT_TRUE(r.passed) << r.report;
        const double P_surf =
            cs.kind == Kind::Tabulated ? tab.surface_probability() : incremental_surface_probability(bins, s);
        EXPECT_NEAR(r.pdf_integral + P_surf, 1.0, 1e-3);
    }
}
