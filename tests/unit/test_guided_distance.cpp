// Guided product distance sampling (docs/theory.md §7): normalisation of both samplers' mixture pdfs
// (quadrature), incremental == tabulated for consistent estimates (§14.8), the sampled pdf equals the
// evaluated one, steps = bins pulled, the filter (7.4) and the degenerate cases of §7.6.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "support/analytic_ray.h"
#include "volguide/core/sampler.h"
#include "volguide/guiding/guided_distance.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// Integral of pdf over every bin by 5-point Gauss-Legendre on 16 sub-intervals (interior nodes only,
// so each bin's half-open end is never evaluated).
double integrate_bins(const std::vector<DistanceBin>& bins, const std::function<float(float)>& pdf) {
    static const double x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                0.9061798459386640};
    static const double w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                0.4786286704993665, 0.2369268850561891};
    double sum = 0.0;
    for (const DistanceBin& b : bins) {
        const int n = 16;
        const double h = (double(b.t1) - b.t0) / n;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < 5; ++j) sum += 0.5 * h * w[j] * pdf(float(b.t0 + h * (i + 0.5 + 0.5 * x[j])));
    }
    return sum;
}

// Random contiguous bins: thick, thin (tau < 1e-6), zero-length, invalid, chromatic, bright, dark.
std::vector<DistanceBin> random_bins(uint32_t seed, bool chromatic) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<DistanceBin> bins;
    float t = 0.f;
    for (int k = 0; k < 12; ++k) {
        DistanceBin b;
        b.t0 = t;
        const float kind = u(rng);
        const float length = kind < 0.08f ? 0.f : 0.05f + 1.5f * u(rng);
        b.t1 = t + length;
        const float s = kind > 0.92f ? 1e-8f : 3.f * u(rng) * u(rng);
        b.sigma_t = chromatic ? Color3(s * (0.2f + 2.f * u(rng)), s, s * (0.2f + 2.f * u(rng))) : Color3(s);
        b.albedo = u(rng);
        b.inscattered = u(rng) < 0.15f ? 0.f : 3.f * u(rng);
        b.L = u(rng) < 0.1f ? 0.f : 2.f * u(rng);  // 0 with Li > 0: the p_max case
        b.valid = u(rng) > 0.1f;
        bins.push_back(b);
        t = b.t1;
    }
    return bins;
}

// Replaces L by the scalar VRE over the proxies, L_k = alpha (1 - T_k) L_i,k + T_k L_{k+1}: estimates
// that are consistent with each other (then the filter is exact and both samplers agree, §14.8).
void make_consistent(std::vector<DistanceBin>& bins, float L_surface) {
    double L = L_surface;
    for (size_t k = bins.size(); k-- > 0;) {
        DistanceBin& b = bins[k];
        const double T = std::exp(-double(b.sigma_t.average()) * (b.t1 - b.t0));
        L = b.albedo * (1.0 - T) * b.inscattered + T * L;
        b.L = float(L);
    }
}

}  // namespace

TEST(GuidedDistance, StrategyChoice) {
    const GuidedDistanceSettings s = settings(0.5f, 0.9f, 1.f);
    EXPECT_EQ(choose_distance_strategy(s, 0.1f), DistanceStrategy::TransmittanceR);
    EXPECT_EQ(choose_distance_strategy(s, 0.2f), DistanceStrategy::TransmittanceG);
    EXPECT_EQ(choose_distance_strategy(s, 0.4f), DistanceStrategy::TransmittanceB);
    EXPECT_EQ(choose_distance_strategy(s, 0.5f), DistanceStrategy::Guided);
    EXPECT_EQ(choose_distance_strategy(settings(0.f, 0.9f, 1.f), 0.f), DistanceStrategy::Guided);
    EXPECT_EQ(choose_distance_strategy(settings(1.f, 0.9f, 1.f), 0.9999f), DistanceStrategy::TransmittanceB);
    // A channel split from the throughput: c_T q_c per channel; a channel with q = 0 is never drawn.
    const Color3 q(0.5f, 0.f, 0.5f);
    const GuidedDistanceSettings t = settings(0.4f, 0.9f, 1.f, DistanceDenominator::Vre, q);
    EXPECT_EQ(choose_distance_strategy(t, 0.19f), DistanceStrategy::TransmittanceR);
    EXPECT_EQ(choose_distance_strategy(t, 0.2f), DistanceStrategy::TransmittanceB);
    EXPECT_EQ(choose_distance_strategy(t, 0.39f), DistanceStrategy::TransmittanceB);
    EXPECT_EQ(choose_distance_strategy(t, 0.4f), DistanceStrategy::Guided);
    EXPECT_EQ(choose_distance_strategy(
                  settings(1.f, 0.9f, 1.f, DistanceDenominator::Vre, Color3(0.f, 1.f, 0.f)), 0.9999f),
              DistanceStrategy::TransmittanceG);
}

// A bin's transmittance probabilities: 1 - T and T within one float ulp of libm's expm1 / exp over
// the whole range of optical depths, across the switch at tau = 0.5 between the thin-bin series
// and exp (the walk's decisions and its pdf must agree to rounding: a coarse approximation here
// would bias the transmittance strategies' weights).
TEST(GuidedDistance, BinTransmittanceMatchesLibm) {
    IncrementalDistanceWalk walk(GuidedDistanceSettings{}, DistanceStrategy::Guided);
    int checked = 0;
    for (int i = 0; i <= 200000; ++i) {
        const float tau = i < 100000 ? 0.5f * float(i) / 100000.f : 0.5f + 20.f * float(i - 100000) / 100000.f;
        DistanceBin bin;
        bin.t0 = 0.f;
        bin.t1 = 1.f;
        bin.sigma_t = Color3(tau);
        const IncrementalDistanceWalk::Bin p = walk.evaluate(bin);
        const float P = -std::expm1(-tau), T = std::exp(-tau);
        ASSERT_LE(std::abs(p.P_T_bar - P), std::nextafter(P, 2.f) - P) << "tau " << tau;
        ASSERT_LE(std::abs(p.T_bar - T), 2.f * (std::nextafter(T, 2.f) - T) + 1e-30f) << "tau " << tau;
        ++checked;
    }
    EXPECT_EQ(checked, 200001);
}

TEST(GuidedDistance, TruncatedExponentialIsNormalisedAndInverts) {
    for (float sigma : {1e-9f, 0.3f, 5.f, 40.f}) {
        const float length = 0.7f;
        double sum = 0.0;
        const int n = 20000;
        for (int i = 0; i < n; ++i)
            sum += truncated_exponential_pdf(sigma, length, (i + 0.5f) * length / n) * length / n;
        EXPECT_NEAR(sum, 1.0, 1e-3) << sigma;
        // Inversion: the cdf at the sampled x equals u.
        for (float u : {0.1f, 0.5f, 0.9f}) {
            const float x = sample_truncated_exponential(sigma, length, u);
            const double cdf = sigma * length <= 1e-6f
                                   ? x / length
                                   : -std::expm1(-double(sigma) * x) / -std::expm1(-double(sigma) * length);
            EXPECT_NEAR(cdf, u, 1e-5) << sigma;
        }
    }
}

TEST(GuidedDistance, PdfIntegratesToOneWithSurfaceProbability) {
    for (uint32_t seed = 1; seed <= 20; ++seed)
        for (bool chromatic : {false, true})
            for (const GuidedDistanceSettings& s :
                 {settings(0.5f, 0.9f, 0.5f), settings(0.5f, 0.9f, 1.f), settings(0.f, 1.f, 0.5f),
                  settings(1.f, 0.9f, 1.f), settings(0.2f, 0.7f, 0.75f),
                  settings(0.5f, 0.9f, 0.5f, DistanceDenominator::Vre),
                  settings(0.5f, 0.9f, 0.5f, DistanceDenominator::Vre, Color3(0.7f, 0.05f, 0.25f)),
                  settings(1.f, 0.9f, 1.f, DistanceDenominator::Incident, Color3(0.f, 0.2f, 0.8f))}) {
                const auto bins = random_bins(seed, chromatic);
                const double inc =
                    integrate_bins(bins, [&](float t) { return incremental_distance_pdf(bins, t, s); }) +
                    incremental_surface_probability(bins, s);
                EXPECT_NEAR(inc, 1.0, 2e-4)
                    << "incremental seed " << seed << " chromatic " << chromatic << " c_T " << s.c_T;
                for (std::optional<float> L_o : {std::optional<float>(), std::optional<float>(0.7f)}) {
                    const TabulatedDistance tab(bins, L_o, s);
                    const double sum =
                        integrate_bins(bins, [&](float t) { return tab.pdf(t); }) + tab.surface_probability();
                    EXPECT_NEAR(sum, 1.0, 2e-4) << "tabulated seed " << seed << " chromatic " << chromatic;
                }
            }
}

TEST(GuidedDistance, IncrementalEqualsTabulatedForConsistentEstimates) {
    // Filter off, and also on: for consistent estimates the filter's extrapolation is exact.
    for (uint32_t seed = 1; seed <= 10; ++seed)
        for (bool chromatic : {false, true})
            for (const GuidedDistanceSettings& s :
                 {settings(0.f, 1.f, 1.f), settings(0.5f, 1.f, 1.f), settings(0.5f, 1.f, 0.5f)}) {
                auto bins = random_bins(seed, chromatic);
                for (DistanceBin& b : bins) b.valid = true;
                const float L_o = 0.8f;
                make_consistent(bins, L_o);
                for (std::optional<float> surface : {std::optional<float>(L_o), std::optional<float>()}) {
                    const TabulatedDistance tab(bins, surface, s);
                    EXPECT_NEAR(tab.surface_probability(), incremental_surface_probability(bins, s), 1e-5);
                    for (int i = 0; i < 300; ++i) {
                        const float t = bins.back().t1 * (i + 0.37f) / 300.f;
                        const float a = incremental_distance_pdf(bins, t, s), b = tab.pdf(t);
                        EXPECT_NEAR(a, b, 1e-4f * std::max(1.f, b))
                            << "seed " << seed << " t " << t << " A " << s.filter_A;
                    }
                }
            }
}

TEST(GuidedDistance, ClampMakesIncrementalDifferFromTabulated) {
    // Power check of the comparison above: a clamp that bites changes the incremental pdf.
    const auto ray = six_bin_ray();
    const auto bins = ray.bins();
    const GuidedDistanceSettings s = settings(0.f, 0.2f, 1.f);
    const TabulatedDistance tab(bins, std::nullopt, s);
    EXPECT_GT(std::abs(tab.surface_probability() - incremental_surface_probability(bins, s)), 1e-2);
}

TEST(GuidedDistance, SampledPdfMatchesEvaluationAndStepsCountBins) {
    for (bool chromatic : {false, true}) {
        const auto ray = six_bin_ray(chromatic);
        auto bins = ray.bins(
            [](size_t k, int which) { return which == 0 ? 1.f + 0.3f * float(k) : 1.7f - 0.2f * float(k); });
        // A zero-length bin in the middle is pulled (counted) but never scatters.
        DistanceBin empty = bins[2];
        empty.t1 = empty.t0;
        bins.insert(bins.begin() + 2, empty);
        for (DistanceDenominator den : {DistanceDenominator::Incident, DistanceDenominator::Vre}) {
            const GuidedDistanceSettings s = settings(0.5f, 0.9f, 0.5f, den, Color3(0.2f, 0.5f, 0.3f));
            const TabulatedDistance tab(bins, std::nullopt, s);
            int medium = 0, surface = 0;
            for (uint64_t i = 0; i < 4000; ++i) {
                Sampler rng(7, 0, i);
                AnalyticRay::Source src{&bins};
                const DistanceSample d = sample_incremental_distance(src, rng, s);
                EXPECT_EQ(size_t(d.steps), src.next);
                if (d.event == DistanceEvent::Medium) {
                    ++medium;
                    const DistanceBin& last = bins[size_t(d.steps) - 1];
                    EXPECT_TRUE(d.t >= last.t0 && d.t < last.t1) << d.t;
                    EXPECT_NEAR(d.pdf, incremental_distance_pdf(bins, d.t, s), 1e-6f * d.pdf);
                } else {
                    ++surface;
                    EXPECT_EQ(d.steps, int(bins.size()));
                    EXPECT_EQ(d.t, bins.back().t1);
                    EXPECT_NEAR(d.pdf, incremental_surface_probability(bins, s), 1e-7f);
                }
                const DistanceSample e = tab.sample(rng);
                if (e.event == DistanceEvent::Medium)
                    EXPECT_NEAR(e.pdf, tab.pdf(e.t), 1e-6f * e.pdf);
                else
                    EXPECT_EQ(e.pdf, tab.surface_probability());
            }
            EXPECT_GT(medium, 100);
            EXPECT_GT(surface, 10);  // T(0, s) ~ 0.1 grey, less than 0.01 in red
        }
    }
}

TEST(GuidedDistance, ConfidenceBlendsTheGuidedProbabilityTowardFreeFlight) {
    DistanceBin b{0.f, 1.f, Color3(0.7f), 0.8f, 1.f, 2.f, true};
    const float P_T = -std::expm1(-0.7f);
    const float N = 0.8f * P_T * 1.f;
    for (DistanceDenominator den : {DistanceDenominator::Incident, DistanceDenominator::Vre}) {
        const GuidedDistanceSettings s = settings(0.f, 0.9f, 1.f, den);
        const float P_G = den == DistanceDenominator::Vre ? N / (N + std::exp(-0.7f) * 2.f) : N / 2.f;
        for (float conf : {1.f, 0.25f, 0.f}) {
            b.confidence = conf;
            const std::vector<DistanceBin> one{b};
            EXPECT_NEAR(incremental_surface_probability(one, s), 1.f - (conf * P_G + (1.f - conf) * P_T),
                        1e-6f);
        }
    }
    // Bins of any confidence keep the mixture normalised.
    for (uint32_t seed = 1; seed <= 10; ++seed) {
        auto bins = random_bins(seed, true);
        for (size_t k = 0; k < bins.size(); ++k) bins[k].confidence = float(k % 4) / 3.f;
        const GuidedDistanceSettings s = settings(0.5f, 0.9f, 0.5f, DistanceDenominator::Vre);
        const double sum = integrate_bins(bins, [&](float t) { return incremental_distance_pdf(bins, t, s); }) +
                           incremental_surface_probability(bins, s);
        EXPECT_NEAR(sum, 1.0, 2e-4) << seed;
    }
}

TEST(GuidedDistance, VreDenominatorMatchesHandComputation) {
    // P^G = N / (N + T L^I) with N = alpha (1 - T) L_i, clamped to max(p_max, 1 - T).
    std::vector<DistanceBin> bins(2);
    bins[0] = {0.f, 1.f, Color3(1.f), 0.5f, 2.f, 3.f, true};
    bins[1] = {1.f, 2.f, Color3(1.f), 1.f, 0.5f, 1.f, true};
    const double T = std::exp(-1.0);
    const double N0 = 0.5 * (1 - T) * 2.0, N1 = 1.0 * (1 - T) * 0.5;
    const double P0 = N0 / (N0 + T * 3.0), P1 = N1 / (N1 + T * 1.0);
    const auto vre = [](float A, float p_max) { return settings(0.f, p_max, A, DistanceDenominator::Vre); };
    EXPECT_NEAR(incremental_surface_probability(bins, vre(1.f, 1.f)), (1 - P0) * (1 - P1), 1e-6);
    // With the filter, L^I of the second bin is the paper's blend (7.4).
    const double L_I1 = 0.75 * (3.0 - N0) / T + 0.25 * 1.0;
    EXPECT_NEAR(incremental_surface_probability(bins, vre(0.25f, 1.f)), (1 - P0) * (1 - N1 / (N1 + T * L_I1)),
                1e-6);

    // An optically thick bin whose lookups disagree (L_i / L = 0.2): the paper's form passes the
    // bin with probability ~ 0.8 although it lets e^-12 through; Vre scatters there like free flight.
    DistanceBin thick{0.f, 1.f, Color3(12.f), 0.9f, 0.2f, 1.f, true};
    const std::vector<DistanceBin> one{thick};
    EXPECT_NEAR(incremental_surface_probability(one, settings(0.f, 0.9f, 1.f)), 1.0 - 0.9 * 0.2, 1e-5);
    const float P_T = -std::expm1(-12.f);
    EXPECT_NEAR(incremental_surface_probability(one, vre(1.f, 0.9f)),
                1.0 - 0.18 / (0.18 * P_T + std::exp(-12.0)) * P_T, 1e-5);
    EXPECT_LT(incremental_surface_probability(one, vre(1.f, 0.9f)), 1e-4);
    // The clamp is max(p_max, 1 - T): a bright thick bin may go up to P^T, a bright thin one to p_max.
    thick.inscattered = 100.f;
    EXPECT_NEAR(incremental_surface_probability(std::vector<DistanceBin>{thick}, vre(1.f, 0.9f)),
                std::exp(-12.f) / 1.f, 1e-6);
    DistanceBin thin{0.f, 1.f, Color3(0.05f), 1.f, 1e6f, 1.f, true};
    EXPECT_NEAR(incremental_surface_probability(std::vector<DistanceBin>{thin}, vre(1.f, 0.9f)), 0.1, 1e-6);
}

TEST(GuidedDistance, StopsPullingBinsAtTheFirstAcceptedScatter) {
    // A bright, thick first bin: the guided strategy scatters there with P^G = p_max and never
    // asks for the second bin.
    std::vector<DistanceBin> bins(2);
    bins[0] = {0.f, 1.f, Color3(3.f), 1.f, 10.f, 1.f, true};
    bins[1] = {1.f, 2.f, Color3(3.f), 1.f, 10.f, 1.f, true};
    const GuidedDistanceSettings s = settings(0.f, 1.f, 1.f);
    Sampler rng(1, 2, 3);
    AnalyticRay::Source src{&bins};
    const DistanceSample d = sample_incremental_distance(src, rng, s);
    EXPECT_EQ(d.event, DistanceEvent::Medium);
    EXPECT_EQ(d.steps, 1);
    EXPECT_EQ(src.next, 1u);
}

TEST(GuidedDistance, FilterMatchesHandComputation) {
    std::vector<DistanceBin> bins(2);
    bins[0] = {0.f, 1.f, Color3(1.f), 0.5f, 2.f, 3.f, true};
    bins[1] = {1.f, 2.f, Color3(1.f), 1.f, 0.5f, 1.f, true};
    const double T = std::exp(-1.0);
    const double P0 = 0.5 * (1 - T) * 2.0 / 3.0;
    const double extrapolated = (3.0 - (1 - T) * 0.5 * 2.0) / T;
    const double L_I = 0.75 * extrapolated + 0.25 * 1.0;  // A = 0.25
    const double P1 = 1.0 * (1 - T) * 0.5 / L_I;
    EXPECT_NEAR(incremental_surface_probability(bins, settings(0.f, 1.f, 0.25f)), (1 - P0) * (1 - P1), 1e-6);
    // Filter off: the raw lookup L = 1.
    EXPECT_NEAR(incremental_surface_probability(bins, settings(0.f, 1.f, 1.f)),
                (1 - P0) * (1 - (1 - T) * 0.5), 1e-6);
    // Guard: through an almost opaque previous bin the filter does not extrapolate.
    bins[0].sigma_t = Color3(20.f);
    const double P0_thick = std::min(1.0, 0.5 * 2.0 / 3.0);
    EXPECT_NEAR(incremental_surface_probability(bins, settings(0.f, 1.f, 0.5f)),
                (1 - P0_thick) * (1 - (1 - T) * 0.5), 1e-6);
}

TEST(GuidedDistance, DegenerateCases) {
    const GuidedDistanceSettings s = settings(0.f, 0.9f, 1.f);
    const DistanceBin base{0.f, 1.f, Color3(0.7f), 0.8f, 1.f, 2.f, true};
    const float T = std::exp(-0.7f);
    auto one = [&](DistanceBin b) { return incremental_surface_probability(std::vector<DistanceBin>{b}, s); };
    auto count_nans = [&](DistanceBin b) {
        std::vector<DistanceBin> bins{b};
        Sampler rng(3, 0, 0);
        AnalyticRay::Source src{&bins};
        return sample_incremental_distance(src, rng, s).nan_fallbacks;
    };

    DistanceBin b = base;
    EXPECT_NEAR(one(b), 1.f - 0.8f * (1.f - T) * 1.f / 2.f, 1e-6f);  // regular
    b.inscattered = NAN;                                                      // NaN -> P^T, counted
    EXPECT_NEAR(one(b), T, 1e-6f);
    EXPECT_EQ(count_nans(b), 1);
    EXPECT_EQ(count_nans(base), 0);
    b = base;
    b.L = NAN;
    EXPECT_NEAR(one(b), T, 1e-6f);
    b = base;
    b.L = 0.f;  // denominator 0, numerator > 0 -> p_max
    EXPECT_NEAR(one(b), 1.f - 0.9f, 1e-6f);
    b.L = -1.f;
    EXPECT_NEAR(one(b), 1.f - 0.9f, 1e-6f);
    b.L = INFINITY;
    EXPECT_NEAR(one(b), 1.f - 0.9f, 1e-6f);
    b = base;
    b.inscattered = 100.f;  // clamp
    EXPECT_NEAR(one(b), 1.f - 0.9f, 1e-6f);
    b = base;
    b.inscattered = 0.f;  // numerator 0 -> P^G = 0, even with L = 0
    EXPECT_NEAR(one(b), 1.f, 1e-7f);
    b.L = 0.f;
    EXPECT_NEAR(one(b), 1.f, 1e-7f);
    b = base;
    b.valid = false;  // invalid -> P^T
    EXPECT_NEAR(one(b), T, 1e-6f);

    // Optically thin bin: uniform density, P^T ~ tau.
    DistanceBin thin = base;
    thin.sigma_t = Color3(1e-8f);
    const GuidedDistanceSettings mixed = settings(0.5f, 0.9f, 1.f);
    const std::vector<DistanceBin> thin_bins{thin};
    EXPECT_EQ(incremental_distance_pdf(thin_bins, 0.1f, mixed),
              incremental_distance_pdf(thin_bins, 0.9f, mixed));
    EXPECT_GT(incremental_distance_pdf(thin_bins, 0.5f, mixed), 0.f);
    EXPECT_NEAR(incremental_surface_probability(thin_bins, mixed), 1.f, 1e-6f);

    // Zero-length bins change nothing; t outside the bins has density 0.
    auto bins = random_bins(5, true);
    DistanceBin empty = bins[3];
    empty.t1 = empty.t0;
    bins.insert(bins.begin() + 3, empty);
    std::vector<DistanceBin> without;
    for (const DistanceBin& x : bins)
        if (x.t1 > x.t0) without.push_back(x);
    ASSERT_LT(without.size(), bins.size());
    const GuidedDistanceSettings f = settings(0.5f, 0.9f, 0.5f);
    EXPECT_EQ(incremental_surface_probability(bins, f), incremental_surface_probability(without, f));
    EXPECT_EQ(TabulatedDistance(bins, std::nullopt, f).surface_probability(),
              TabulatedDistance(without, std::nullopt, f).surface_probability());
    for (int i = 0; i < 100; ++i) {
        const float t = bins.back().t1 * (i + 0.5f) / 100.f;
        EXPECT_EQ(incremental_distance_pdf(bins, t, f), incremental_distance_pdf(without, t, f));
        EXPECT_NEAR(TabulatedDistance(bins, std::nullopt, f).pdf(t),
                    TabulatedDistance(without, std::nullopt, f).pdf(t), 1e-6f);
    }
    EXPECT_EQ(incremental_distance_pdf(bins, -0.1f, f), 0.f);
    EXPECT_EQ(incremental_distance_pdf(bins, bins.back().t1, f), 0.f);
    EXPECT_EQ(TabulatedDistance(bins, std::nullopt, f).pdf(bins.back().t1 + 1.f), 0.f);

    // No bins at all: the surface with probability 1.
    std::vector<DistanceBin> none;
    Sampler rng(1, 1, 1);
    AnalyticRay::Source src{&none};
    const DistanceSample d = sample_incremental_distance(src, rng, f);
    EXPECT_EQ(d.event, DistanceEvent::Surface);
    EXPECT_EQ(d.pdf, 1.f);
    EXPECT_EQ(d.steps, 0);
}

TEST(GuidedDistance, TabulatedAllDarkGoesToSurfaceAndInvalidBinsAreReachable) {
    std::vector<DistanceBin> bins(3);
    for (int k = 0; k < 3; ++k)
        bins[size_t(k)] = {float(k), float(k + 1), Color3(0.5f), 0.9f, 0.f, 0.f, true};
    const GuidedDistanceSettings s = settings(0.f, 0.9f, 1.f);
    EXPECT_EQ(TabulatedDistance(bins, 0.f, s).surface_probability(), 1.f);
    bins[1].valid = false;  // unknown: treated like the brightest valid bin (here 0) ...
    bins[0].inscattered = 2.f;       // ... which now is 2
    const TabulatedDistance tab(bins, 0.f, s);
    EXPECT_GT(tab.pdf(1.5f), 0.f);
}
