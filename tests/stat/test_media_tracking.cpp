// Heterogeneous-medium estimators against quadrature (oracles.md §4):
//  - ratio and residual ratio tracking: E[T] = exp(-tau) per channel, tight and 10x loose majorant;
//  - delta tracking (grey): the optical depth at the sampled collision is Exp(1) (KS test);
//  - spectral tracking (chromatic): E[w 1{scattered} f(t)] = int T_c sigma_s,c f dt and
//    E[w 1{escaped}] = T_c(s), tight and 10x loose majorant.
// z-tests use |z| < 4 (per-test alpha 6e-5; the whole file has < 100 tests).
#include <gtest/gtest.h>

#include <algorithm>

#include "support/media_test_util.h"
#include "support/running_stats.h"

using namespace volguide;
using namespace volguide::test;

namespace {

constexpr double kZ = 4.0;
constexpr double kFloor = 1e-6;  // standard-error floor: rounding noise of exact estimates

// Kolmogorov-Smirnov distance of a sample from Uniform(0, 1).
double ks_uniform(std::vector<double> u) {
    std::sort(u.begin(), u.end());
    const double n = double(u.size());
    double d = 0.0;
    for (size_t i = 0; i < u.size(); ++i) d = std::max({d, std::abs(u[i] - i / n), std::abs(u[i] - (i + 1) / n)});
    return d;
}

}  // namespace

TEST(MediaTracking, RatioAndResidualRatioTransmittance) {
    auto m = cloud_medium(3, Color3(0.f), 6.f);
    const auto rays = test_rays();
    for (size_t ri = 0; ri < rays.size(); ++ri) {
        const TestRay& r = rays[ri];
        RayProfile prof(*m, r.ray, profile_length(*m, r));
        for (auto est : {TransmittanceEstimator::Ratio, TransmittanceEstimator::ResidualRatio})
            for (float ms : {1.f, 10.f}) {
                m->set_transmittance_estimator(est);
                m->set_majorant_scale(ms);
                RunningStats st[3];
                const int n = 20000;
                for (int i = 0; i < n; ++i) {
                    Sampler s(17 + ri, uint64_t(ms), uint64_t(i), uint64_t(est));
                    const Color3 tr = m->transmittance(r.ray, r.tmax, s);
                    ASSERT_TRUE(tr.is_finite());
                    for (int c = 0; c < 3; ++c) st[c].add(tr[c]);
                }
                for (int c = 0; c < 3; ++c) {
                    const double exact = std::exp(-prof.total_tau(c));
                    EXPECT_LT(st[c].z(exact, kFloor), kZ) << "ray " << ri << " est " << int(est) << " majorant x" << ms
                                                  << " channel " << c << ": " << st[c].mean() << " vs " << exact
                                                  << " (tau " << prof.total_tau(c) << ")";
                }
            }
    }
    m->set_majorant_scale(1.f);
}

TEST(MediaTracking, TransmittanceTestCanFail) {
    // The same z-test must reject a 5 % error in tau.
    auto m = cloud_medium(1, Color3(0.f), 6.f);
    const TestRay r = test_rays()[0];
    RayProfile prof(*m, r.ray, profile_length(*m, r));
    RunningStats st;
    for (int i = 0; i < 20000; ++i) {
        Sampler s(3, 0, uint64_t(i));
        st.add(m->transmittance(r.ray, r.tmax, s).r);
    }
    ASSERT_GT(prof.total_tau(0), 0.5);
    EXPECT_LT(st.z(std::exp(-prof.total_tau(0))), kZ);
    EXPECT_GT(st.z(std::exp(-1.05 * prof.total_tau(0))), kZ);
}

TEST(MediaTracking, DeltaTrackingDepthIsExponential) {
    auto m = cloud_medium(1, Color3(0.7f), 4.f);
    const auto rays = test_rays();
    for (size_t ri = 0; ri < rays.size(); ++ri) {
        const TestRay& r = rays[ri];
        RayProfile prof(*m, r.ray, profile_length(*m, r));
        const double total = prof.total_tau(0);
        for (float ms : {1.f, 10.f}) {
            m->set_majorant_scale(ms);
            const int n = 20000;
            std::vector<double> u(n), u_wrong(n);
            Sampler extra(99, ri, uint64_t(ms));
            for (int i = 0; i < n; ++i) {
                Sampler s(5 + ri, uint64_t(ms), uint64_t(i));
                FreeFlightSample fs = m->sample_free_flight(r.ray, r.tmax, Color3(1.f), s);
                if (fs.scattered) {
                    ASSERT_LT(fs.t, r.tmax);
                    EXPECT_NEAR(fs.weight.r, 0.7f, 1e-5f);  // grey: the weight is the albedo
                    u[i] = -std::expm1(-prof.tau_at(0, fs.t));
                    u_wrong[i] = -std::expm1(-1.1 * prof.tau_at(0, fs.t));
                } else {
                    EXPECT_NEAR(fs.weight.r, 1.f, 1e-5f);
                    // Escapes carry the mass exp(-total): spread it uniformly over its range.
                    u[i] = -std::expm1(-total) + std::exp(-total) * extra.next_1d();
                    u_wrong[i] = -std::expm1(-1.1 * total) + std::exp(-1.1 * total) * extra.next_1d();
                }
            }
            // Kolmogorov critical value for alpha = 0.001: 1.95 / sqrt(n). A 10 % error in tau must fail.
            const double crit = 1.95 / std::sqrt(double(n));
            EXPECT_LT(ks_uniform(u), crit) << "ray " << ri << " majorant x" << ms << " tau " << total;
            EXPECT_GT(ks_uniform(u_wrong), crit) << "ray " << ri << " majorant x" << ms << " tau " << total;
        }
    }
    m->set_majorant_scale(1.f);
}

TEST(MediaTracking, SpectralTrackingWeights) {
    auto m = cloud_medium(3, Color3(0.9f, 0.5f, 0.99f), 4.f);
    const auto rays = test_rays();
    for (size_t ri = 0; ri < rays.size(); ++ri) {
        const TestRay& r = rays[ri];
        RayProfile prof(*m, r.ray, profile_length(*m, r));
        for (float ms : {1.f, 10.f}) {
            m->set_majorant_scale(ms);
            RunningStats scat[3], scat_t[3], esc[3];
            const int n = 40000;
            for (int i = 0; i < n; ++i) {
                Sampler s(31 + ri, uint64_t(ms), uint64_t(i));
                FreeFlightSample fs = m->sample_free_flight(r.ray, r.tmax, Color3(1.f), s);
                ASSERT_TRUE(fs.weight.is_finite());
                if (fs.scattered) {
                    const MediumCoefficients ref = m->eval(fs.mi.p);
                    ASSERT_NEAR(fs.mi.coeffs.sigma_t.r, ref.sigma_t.r, 1e-4f);
                    for (int c = 0; c < 3; ++c)
                        ASSERT_NEAR(fs.weight[c], fs.flight_weight[c] * fs.mi.coeffs.sigma_s[c],
                                    1e-5f * std::abs(fs.weight[c]) + 1e-7f);
                } else {
                    ASSERT_EQ(fs.weight, fs.flight_weight);
                }
                for (int c = 0; c < 3; ++c) {
                    scat[c].add(fs.scattered ? fs.weight[c] : 0.0);
                    scat_t[c].add(fs.scattered ? fs.weight[c] * fs.t : 0.0);
                    esc[c].add(fs.scattered ? 0.0 : fs.weight[c]);
                }
            }
            for (int c = 0; c < 3; ++c) {
                const double e_scat = prof.scatter_integral(c, [](double) { return 1.0; });
                const double e_scat_t = prof.scatter_integral(c, [](double t) { return t; });
                const double e_esc = std::exp(-prof.total_tau(c));
                const std::string where = "ray " + std::to_string(ri) + " majorant x" + std::to_string(ms) +
                                          " channel " + std::to_string(c);
                EXPECT_LT(scat[c].z(e_scat, kFloor), kZ) << where << ": " << scat[c].mean() << " vs " << e_scat;
                EXPECT_LT(scat_t[c].z(e_scat_t, kFloor), kZ) << where << ": " << scat_t[c].mean() << " vs " << e_scat_t;
                EXPECT_LT(esc[c].z(e_esc, kFloor), kZ) << where << ": " << esc[c].mean() << " vs " << e_esc;
            }
        }
    }
    m->set_majorant_scale(1.f);
}

TEST(MediaTracking, RaysCrossTheCloud) {
    // Guards the tests above against rays that see (almost) no medium.
    auto m = cloud_medium(3, Color3(0.f), 6.f);
    for (const TestRay& r : test_rays()) {
        RayProfile prof(*m, r.ray, profile_length(*m, r));
        EXPECT_GT(prof.total_tau(0), 1.0);
        EXPECT_GT(prof.total_tau(2), 0.2);
    }
}

TEST(MediaTracking, MissingTheBoxIsFree) {
    auto m = cloud_medium(3, Color3(0.5f), 4.f);
    const Ray ray(Point3f(0.f, 5.f, 0.f), Vec3f(1.f, 0.f, 0.f));
    Sampler s(1, 0, 0);
    FreeFlightSample fs = m->sample_free_flight(ray, Infinity, Color3(1.f), s);
    EXPECT_FALSE(fs.scattered);
    EXPECT_EQ(fs.weight, Color3(1.f));
    EXPECT_EQ(m->transmittance(ray, Infinity, s), Color3(1.f));
    EXPECT_EQ(s.dimension(), 0u);  // no random numbers spent
}
