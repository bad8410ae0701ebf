// distance="vsp"'s homogeneous segment decision (integrators/guided/walk/vsp_distance.h, docs/theory.md
// §7.10): for grey and chromatic extinction, finite and infinite segments, guided probabilities
// below, at and above the unguided one and defensive shares 0.1 and 0.5:
//  - the distance conditioned on scattering matches p(t | scatter) (chi-square over t in (0, s),
//    mapped to (0, 1) by the unguided CDF so the bins are balanced), and P(scatter) = P (chi-square
//    of the two outcomes);
//  - int p(t | scatter) dt = 1 (quadrature), so P int p + P(pass) = 1;
//  - the weights are exact: E[w 1{scatter} f(t)] = int_0^s T_c sigma_s,c f(t) dt and
//    E[w 1{pass}] = T_c(s) per channel (z-tests, |z| < 4);
//  - the equiangular share (§7.10.1): the mixture's conditional distance by chi-square against its
//    CDF, its pdf integrating to 1, and its weights exact by the same z-tests;
//  - P = P_u gives free flight's weights (T / the spectral mixture density); a guided probability
//    that never scatters (defensive share 0) must fail the scatter z-test (the test can fail).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "support/chi2.h"
#include "support/media_test_util.h"
#include "support/running_stats.h"
#include "volguide/integrators/guided/walk/vsp_distance.h"
#include "volguide/media/homogeneous_transmittance.h"
#include "volguide/media/spectral_mis.h"

using namespace volguide;
using namespace volguide::test;

namespace {

struct Case {
    Color3 sigma_t;
    float s;
    Color3 throughput;
};
const Case kCases[] = {{Color3(0.8f), 1.5f, Color3(1.f)},
                       {Color3(0.5f, 1.f, 2.5f), 1.2f, Color3(0.2f, 1.f, 3.f)},
                       {Color3(0.5f, 1.f, 2.5f), Infinity, Color3(1.f, 0.5f, 0.2f)},
                       {Color3(0.f, 1.f, 4.f), 0.7f, Color3(1.f)}};

// The unguided CDF of the truncated mixture (for balanced bins): F(t) = sum_c q_c (1 - T_c(t)) / P_u.
double mixture_cdf(const Case& k, const Color3& q, double t, double pu) {
    double f = 0.0;
    for (int c = 0; c < 3; ++c)
        if (k.sigma_t[c] > 0.f) f += q[c] * -std::expm1(-double(k.sigma_t[c]) * t);
    return f / pu;
}

}  // namespace

TEST(VspDistance, ConditionalDistanceChiSquare) {
    for (const Case& k : kCases)
        for (float guided : {0.05f, 0.5f, 0.97f}) {
            SCOPED_TRACE(testing::Message() << "sigma_t " << k.sigma_t.g << " s " << k.s << " guided " << guided);
            const Color3 q = channel_probabilities(k.throughput);
            const HomogeneousVsp vsp(k.sigma_t, k.s, q);
            const float P = vsp.probability(guided, 0.5f);
            const int bins = 40;
            std::vector<uint64_t> counts(bins + 1, 0);  // the last: passes
            const int n = 200000;
            for (int i = 0; i < n; ++i) {
                Sampler s(3, 0, uint64_t(i));
                const float u0 = s.next_1d(), u1 = s.next_1d(), u2 = s.next_1d();
                const HomogeneousVsp::Sample x = vsp.sample(P, u0, u1, u2);
                if (!x.scattered) {
                    ++counts[bins];
                    continue;
                }
                ASSERT_GE(x.t, 0.f);
                ASSERT_LT(x.t, k.s);
                const double f = mixture_cdf(k, q, x.t, vsp.unguided());
                ++counts[std::min(bins - 1, int(f * bins))];
            }
            // Each CDF bin holds mass P / bins, the passes 1 - P.
            std::vector<double> prob(bins, double(P) / bins);
            prob.push_back(1.0 - P);
            ChiSquareOptions opt;
            opt.test_count = 4 * 3;
            const ChiSquareResult r = chi2_test_discrete(counts, prob, opt);
            EXPECT_TRUE(r.passed) << r.report;
        }
}

TEST(VspDistance, ConditionalPdfIntegratesToOne) {
    for (const Case& k : kCases) {
        const HomogeneousVsp vsp(k.sigma_t, k.s, channel_probabilities(k.throughput));
        const double end = std::isinf(k.s) ? 40.0 : double(k.s);  // e^(-0.5 * 40): negligible
        const int m = 200000;
        double integral = 0.0;
        for (int i = 0; i < m; ++i) integral += vsp.conditional_pdf(float((i + 0.5) * end / m)) * end / m;
        EXPECT_NEAR(integral, 1.0, 1e-3) << "sigma_t " << k.sigma_t.b << " s " << k.s;
        // P int p + P(pass) = 1 for the mixture's P.
        const float P = vsp.probability(0.3f, 0.5f);
        EXPECT_NEAR(P * integral + (1.0 - P), 1.0, 1e-3);
        EXPECT_EQ(vsp.conditional_pdf(-0.1f), 0.f);
        if (!std::isinf(k.s)) {
            EXPECT_EQ(vsp.conditional_pdf(k.s * 1.01f), 0.f);
        }
    }
}

// Runs n decisions and z-tests the weighted expectations per channel (albedo 0.7); returns the
// largest |z| of the scatter mass.
// `equi`: the equiangular share.
static double check_weights(const Case& k, float guided, float c, int n, bool expect_pass,
                            const VspEquiangular& equi = {}) {
    const Color3 q = channel_probabilities(k.throughput);
    const HomogeneousVsp vsp(k.sigma_t, k.s, q);
    const float P = vsp.probability(guided, c);
    const float albedo = 0.7f;
    RunningStats scat[3], scat_t[3], pass[3];
    for (int i = 0; i < n; ++i) {
        Sampler s(9, 0, uint64_t(i));
        const float u0 = s.next_1d(), u1 = s.next_1d(), u2 = s.next_1d();
        const HomogeneousVsp::Sample x = vsp.sample(P, u0, u1, u2, equi);
        EXPECT_TRUE(x.flight_weight.is_finite());
        for (int ch = 0; ch < 3; ++ch) {
            const double w = x.flight_weight[ch] * (x.scattered ? k.sigma_t[ch] * albedo : 1.f);
            scat[ch].add(x.scattered ? w : 0.0);
            scat_t[ch].add(x.scattered ? w * x.t : 0.0);
            pass[ch].add(x.scattered ? 0.0 : w);
        }
    }
    double worst = 0.0;
    for (int ch = 0; ch < 3; ++ch) {
        const double sig = k.sigma_t[ch], s = k.s;
        const double tr = sig > 0 ? (std::isinf(s) ? 0.0 : std::exp(-sig * s)) : 1.0;
        const double mass = albedo * (1.0 - tr);
        const double first = sig > 0 ? albedo * (std::isinf(s) ? 1.0 / sig : (1.0 - tr * (1.0 + sig * s)) / sig) : 0.0;
        const double z = scat[ch].z(mass, 1e-6);
        worst = std::max(worst, z);
        if (expect_pass) {
            EXPECT_LT(z, 4.0) << "channel " << ch << " scatter " << scat[ch].mean() << " vs " << mass;
            EXPECT_LT(scat_t[ch].z(first, 1e-6), 4.0) << "channel " << ch << " scatter t";
            EXPECT_LT(pass[ch].z(tr, 1e-6), 4.0) << "channel " << ch << " pass " << pass[ch].mean() << " vs " << tr;
        }
    }
    return worst;
}

TEST(VspDistance, WeightsAreExact) {
    for (const Case& k : kCases)
        for (float guided : {0.02f, 0.6f, 1.f})
            for (float c : {0.1f, 0.5f}) {
                SCOPED_TRACE(testing::Message() << "sigma_t " << k.sigma_t.b << " s " << k.s << " guided " << guided
                                                << " c " << c);
                check_weights(k, guided, c, 100000, true);
            }
}

TEST(VspDistance, ANeverScatteringGuideFails) {
    // c = 0 and P_G = 0: nothing ever scatters, the scatter mass is missing.
    const Case k = kCases[0];
    EXPECT_GT(check_weights(k, 0.f, 0.f, 20000, false), 8.0);
}

TEST(VspDistance, UnguidedProbabilityIsFreeFlight) {
    for (const Case& k : kCases) {
        const Color3 q = channel_probabilities(k.throughput);
        const HomogeneousVsp vsp(k.sigma_t, k.s, q);
        EXPECT_EQ(vsp.probability(std::nanf(""), 0.3f), vsp.unguided());
        const float P = vsp.unguided();
        for (int i = 0; i < 2000; ++i) {
            Sampler s(5, 0, uint64_t(i));
            const float u0 = s.next_1d(), u1 = s.next_1d(), u2 = s.next_1d();
            const HomogeneousVsp::Sample x = vsp.sample(P, u0, u1, u2);
            if (!x.scattered) {
                const float esc = spectral_escape_probability(k.sigma_t, q, k.s);
                if (esc > 0.f) {
                    for (int ch = 0; ch < 3; ++ch)
                        EXPECT_NEAR(x.flight_weight[ch], transmittance_rgb(k.sigma_t, k.s)[ch] / esc,
                                    1e-3f * (1.f + x.flight_weight[ch]));
                }
                continue;
            }
            const float dens = spectral_distance_pdf(k.sigma_t, q, x.t);
            for (int ch = 0; ch < 3; ++ch)
                EXPECT_NEAR(x.flight_weight[ch], transmittance_rgb(k.sigma_t, x.t)[ch] / dens,
                            1e-3f * (1.f + x.flight_weight[ch]));
        }
    }
    // Nothing to scatter: always pass with weight 1; an opaque infinite segment always scatters.
    const HomogeneousVsp empty(Color3(0.f), 2.f, Color3(1.f / 3.f));
    EXPECT_EQ(empty.probability(0.9f, 0.5f), 0.f);
    const HomogeneousVsp opaque(Color3(1.f), Infinity, Color3(1.f / 3.f));
    EXPECT_EQ(opaque.probability(0.2f, 0.5f), 1.f);
}

// The equiangular share (docs/theory.md §7.10.1): the conditional distance is the mixture
// (1 - e) p_ff(t | scatter) + e p_eq(t | y) for a light point y off the ray (far and close to the
// line, where p_eq is peaked). Its CDF here is written independently of the sampler: the free
// flight's by mixture_cdf, the equiangular one by the angle, (atan((t - D0) / D) - theta_a) / (theta_b - theta_a).
namespace {
struct VspEquiLight {
    Point3f y;
};
const VspEquiLight kVspEquiLights[] = {{Point3f(0.6f, 0.8f, 0.f)}, {Point3f(0.3f, 0.05f, 0.02f)}};

double vsp_equi_cdf(const Point3f& y, double s, double t) {
    // The ray: origin 0, direction +x.
    const double delta = y.x, dist = std::hypot(double(y.y), double(y.z));
    const double a = std::atan2(-delta, dist), b = std::isinf(s) ? 0.5 * 3.14159265358979323846 : std::atan2(s - delta, dist);
    return (std::atan2(t - delta, dist) - a) / (b - a);
}
}  // namespace

TEST(VspDistance, EquiangularMixtureChiSquare) {
    const Ray ray(Point3f(0.f), Vec3f(1.f, 0.f, 0.f));
    for (const Case& k : kCases)
        for (const VspEquiLight& light : kVspEquiLights)
            for (float e : {0.3f, 0.7f, 1.f}) {
                SCOPED_TRACE(testing::Message() << "sigma_t " << k.sigma_t.b << " s " << k.s << " light y " << light.y.y
                                                << " e " << e);
                const Color3 q = channel_probabilities(k.throughput);
                const HomogeneousVsp vsp(k.sigma_t, k.s, q);
                const EquiangularSampler eq(ray.o, ray.d, k.s, light.y);
                ASSERT_TRUE(eq.valid());
                const VspEquiangular equi{&eq, e};
                const float P = vsp.probability(0.6f, 0.5f);
                const int bins = 40;
                std::vector<uint64_t> counts(bins + 1, 0);  // the last: passes
                const int n = 200000;
                for (int i = 0; i < n; ++i) {
                    Sampler sm(13, 0, uint64_t(i));
                    const float u0 = sm.next_1d(), u1 = sm.next_1d(), u2 = sm.next_1d();
                    const HomogeneousVsp::Sample x = vsp.sample(P, u0, u1, u2, equi);
                    if (!x.scattered) {
                        ++counts[bins];
                        continue;
                    }
                    ASSERT_GE(x.t, 0.f);
                    ASSERT_LT(x.t, k.s);
                    // The pdf the sample reports is the mixture's.
                    ASSERT_NEAR(x.pdf, P * vsp.conditional_pdf(x.t, equi), 1e-5f * x.pdf);
                    const double f = (1.0 - e) * mixture_cdf(k, q, x.t, vsp.unguided()) + e * vsp_equi_cdf(light.y, k.s, x.t);
                    ++counts[std::clamp(int(f * bins), 0, bins - 1)];
                }
                std::vector<double> prob(bins, double(P) / bins);
                prob.push_back(1.0 - P);
                ChiSquareOptions opt;
                opt.test_count = 4 * 2 * 3;
                const ChiSquareResult r = chi2_test_discrete(counts, prob, opt);
                EXPECT_TRUE(r.passed) << r.report;
            }
}

TEST(VspDistance, EquiangularMixturePdfIntegratesToOne) {
    const Ray ray(Point3f(0.f), Vec3f(1.f, 0.f, 0.f));
    for (const Case& k : kCases)
        for (const VspEquiLight& light : kVspEquiLights) {
            const HomogeneousVsp vsp(k.sigma_t, k.s, channel_probabilities(k.throughput));
            const EquiangularSampler eq(ray.o, ray.d, k.s, light.y);
            const float e = 0.4f;
            const VspEquiangular equi{&eq, e};
            const double end = std::isinf(k.s) ? 40.0 : double(k.s);
            const int m = 400000;
            double integral = 0.0;
            for (int i = 0; i < m; ++i) integral += vsp.conditional_pdf(float((i + 0.5) * end / m), equi) * end / m;
            // Beyond 40 on an infinite segment: the free flight's tail is negligible, the equiangular one is not.
            if (std::isinf(k.s)) integral += e * (1.0 - vsp_equi_cdf(light.y, k.s, end));
            EXPECT_NEAR(integral, 1.0, 2e-3) << "sigma_t " << k.sigma_t.b << " s " << k.s << " light y " << light.y.y;
            const float P = vsp.probability(0.3f, 0.5f);
            EXPECT_NEAR(P * integral + (1.0 - P), 1.0, 2e-3);
            EXPECT_EQ(vsp.conditional_pdf(-0.1f, equi), 0.f);
            // No light to aim at (or share 0): the free flight's density, bit for bit.
            EXPECT_EQ(vsp.conditional_pdf(0.3f, VspEquiangular{nullptr, e}), vsp.conditional_pdf(0.3f));
            EXPECT_EQ(vsp.conditional_pdf(0.3f, VspEquiangular{&eq, 0.f}), vsp.conditional_pdf(0.3f));
        }
}

TEST(VspDistance, EquiangularMixtureWeightsAreExact) {
    const Ray ray(Point3f(0.f), Vec3f(1.f, 0.f, 0.f));
    for (const Case& k : kCases)
        for (const VspEquiLight& light : kVspEquiLights)
            for (float e : {0.5f, 1.f}) {
                SCOPED_TRACE(testing::Message() << "sigma_t " << k.sigma_t.b << " s " << k.s << " light y " << light.y.y
                                                << " e " << e);
                const EquiangularSampler eq(ray.o, ray.d, k.s, light.y);
                check_weights(k, 0.6f, 0.3f, 100000, true, VspEquiangular{&eq, e});
            }
}

// Heterogeneous media: resampled_segment_flight (the segment's tentative collisions resampled by a
// one-slot reservoir, docs/theory.md §7.10) against quadrature on the tracking tests' procedural
// cloud: E[w 1{scattered}], E[w 1{scattered} t] and E[w 1{passed}] per channel, grey and chromatic,
// tight and 10x loose majorant, for fixed probabilities, the unguided estimate and a mixture.
static double check_resampled(HeterogeneousMedium& m, const std::function<float(float)>& probability, int n,
                              uint64_t seed, bool expect_pass) {
    double worst = 0.0;
    const auto rays = test_rays();
    for (size_t ri = 0; ri < rays.size(); ++ri) {
        const TestRay& r = rays[ri];
        RayProfile prof(m, r.ray, profile_length(m, r));
        for (float ms : {1.f, 10.f}) {
            m.set_majorant_scale(ms);
            RunningStats scat[3], scat_t[3], esc[3];
            for (int i = 0; i < n; ++i) {
                Sampler s(seed + ri, uint64_t(ms), uint64_t(i));
                const FreeFlightSample fs =
                    resampled_segment_flight(m, r.ray, r.tmax, Color3(0.3f, 1.f, 0.6f), probability, s);
                EXPECT_TRUE(fs.weight.is_finite());
                if (fs.scattered) {
                    EXPECT_LT(fs.t, r.tmax);
                }
                for (int c = 0; c < 3; ++c) {
                    scat[c].add(fs.scattered ? fs.weight[c] : 0.0);
                    scat_t[c].add(fs.scattered ? fs.weight[c] * fs.t : 0.0);
                    esc[c].add(fs.scattered ? 0.0 : fs.weight[c]);
                }
            }
            for (int c = 0; c < 3; ++c) {
                const double want[3] = {prof.scatter_integral(c, [](double) { return 1.0; }),
                                        prof.scatter_integral(c, [](double t) { return t; }),
                                        std::exp(-prof.total_tau(c))};
                const RunningStats* got[3] = {&scat[c], &scat_t[c], &esc[c]};
                for (int k = 0; k < 3; ++k) {
                    const double z = got[k]->z(want[k], 1e-6);
                    worst = std::max(worst, z);
                    if (expect_pass) {
                        EXPECT_LT(z, 4.0) << "ray " << ri << " majorant x" << ms << " channel " << c << " moment " << k
                                          << ": " << got[k]->mean() << " vs " << want[k];
                    }
                }
            }
        }
    }
    m.set_majorant_scale(1.f);
    return worst;
}

TEST(VspDistance, ResampledSegmentGrey) {
    auto m = cloud_medium(1, Color3(0.7f), 4.f);
    for (float fixed : {0.1f, 0.9f}) {
        SCOPED_TRACE(fixed);
        check_resampled(*m, [fixed](float) { return fixed; }, 20000, 500, true);
    }
    check_resampled(*m, [](float unguided) { return unguided; }, 20000, 510, true);
}

TEST(VspDistance, ResampledSegmentChromatic) {
    auto m = cloud_medium(3, Color3(0.9f, 0.5f, 0.99f), 4.f);
    check_resampled(*m, [](float unguided) { return 0.5f * unguided + 0.25f; }, 20000, 600, true);
}

TEST(VspDistance, ResampledSegmentBiasIsDetected) {
    // A probability of 0 is held at kResampledMinProbability (unbiased, only noisier): the z-test
    // above must detect its scatter branch weighted by half (the test can fail).
    auto m = cloud_medium(1, Color3(0.7f), 4.f);
    const auto rays = test_rays();
    const TestRay& r = rays[0];
    RayProfile prof(*m, r.ray, profile_length(*m, r));
    RunningStats half;
    for (int i = 0; i < 20000; ++i) {
        Sampler s(700, 0, uint64_t(i));
        const FreeFlightSample fs = resampled_segment_flight(*m, r.ray, r.tmax, Color3(1.f), [](float) { return 0.f; }, s);
        half.add(fs.scattered ? 0.5 * fs.weight.g : 0.0);
    }
    EXPECT_GT(half.z(prof.scatter_integral(1, [](double) { return 1.0; }), 1e-6), 8.0);
}
