// Homogeneous media: the closed-form free-flight sampler with one-sample spectral MIS must give
// E[w 1{scattered} f(t)] = int_0^s T_c(t) sigma_s,c f(t) dt and E[w 1{escaped}] = T_c(s) per channel
// (z-tests), and transmittance() is exact. The free flight is sampled in closed form; the
// majorant walk it hands to callers is one segment at the largest channel's rate.
#include <gtest/gtest.h>

#include "support/running_stats.h"
#include "volguide/media/guided_tracking.h"
#include "volguide/media/homogeneous.h"
#include "volguide/media/phase_isotropic.h"

using namespace volguide;
using namespace volguide::test;

namespace {

std::shared_ptr<HomogeneousMedium> make_medium(const Color3& sigma_t, const Color3& albedo) {
    return std::make_shared<HomogeneousMedium>(sigma_t, std::make_shared<Volume>(VoxelGrid(albedo), Transform()),
                                               std::make_shared<IsotropicPhase>());
}

// Exact per-channel expectations over t in [0, s] for f(t) = 1 and f(t) = t.
double scatter_mass(double sigma, double albedo, double s) { return sigma > 0 ? albedo * -std::expm1(-sigma * s) : 0.0; }
double scatter_first_moment(double sigma, double albedo, double s) {
    // int_0^s t sigma e^{-sigma t} dt = (1 - e^{-sigma s}(1 + sigma s)) / sigma
    if (sigma == 0.0) return 0.0;
    if (std::isinf(s)) return albedo / sigma;
    return albedo * (1.0 - std::exp(-sigma * s) * (1.0 + sigma * s)) / sigma;
}

// `throughput` only steers the channel choice: the expectations do not depend on it.
void check_medium(const Color3& sigma_t, const Color3& albedo, float s, int n, uint64_t seed,
                  const Color3& throughput = Color3(1.f)) {
    auto m = make_medium(sigma_t, albedo);
    const Ray ray(Point3f(0.3f, -1.f, 2.f), normalize(Vec3f(1.f, 2.f, -0.5f)));
    RunningStats scat[3], scat_t[3], esc[3], flight[3];
    for (int i = 0; i < n; ++i) {
        Sampler sampler(seed, 0, uint64_t(i));
        FreeFlightSample fs = m->sample_free_flight(ray, s, throughput, sampler);
        ASSERT_TRUE(fs.weight.is_finite());
        if (fs.scattered) {
            ASSERT_LT(fs.t, s);
            ASSERT_NEAR(norm(fs.mi.p - ray(fs.t)), 0.f, 1e-5f);
            ASSERT_EQ(fs.mi.wi, -ray.d);
            ASSERT_EQ(fs.mi.medium, m.get());
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(fs.weight[c], fs.flight_weight[c] * fs.mi.coeffs.sigma_s[c], 1e-5f * fs.weight[c] + 1e-7f);
            // E[flight_weight] over collisions = int_0^s T_c(t) dt (the collision estimator's 1/sigma_t).
            for (int c = 0; c < 3; ++c) flight[c].add(fs.flight_weight[c]);
        } else {
            for (int c = 0; c < 3; ++c) flight[c].add(0.0);
        }
        for (int c = 0; c < 3; ++c) {
            scat[c].add(fs.scattered ? fs.weight[c] : 0.0);
            scat_t[c].add(fs.scattered ? fs.weight[c] * fs.t : 0.0);
            esc[c].add(fs.scattered ? 0.0 : fs.weight[c]);
        }
    }
    for (int c = 0; c < 3; ++c) {
        const double sig = sigma_t[c], a = albedo[c];
        const double e_esc = std::isinf(s) ? (sig > 0 ? 0.0 : 1.0) : std::exp(-sig * s);
        EXPECT_LT(scat[c].z(scatter_mass(sig, a, s)), 4.5) << "channel " << c << " mean " << scat[c].mean();
        EXPECT_LT(scat_t[c].z(scatter_first_moment(sig, a, s)), 4.5) << "channel " << c;
        EXPECT_LT(esc[c].z(e_esc), 4.5) << "channel " << c << " mean " << esc[c].mean() << " exact " << e_esc;
        if (sig > 0) {
            const double e_flight = std::isinf(s) ? 1.0 / sig : -std::expm1(-sig * s) / sig;
            EXPECT_LT(flight[c].z(e_flight), 4.5) << "channel " << c << " flight weight " << flight[c].mean();
        }
    }
}

}  // namespace

TEST(MediaHomogeneous, ChromaticFreeFlightWeights) {
    check_medium(Color3(1.f, 0.2f, 3.f), Color3(0.5f, 0.9f, 0.99f), 1.5f, 200000, 1);
    // Mitsuba test-scene values (scale 10).
    check_medium(Color3(10.f, 2.f, 10.f), Color3(0.5f, 0.5f, 0.99f), 0.4f, 200000, 2);
    // A channel without extinction and an unbounded segment.
    check_medium(Color3(0.f, 0.7f, 2.f), Color3(0.3f), Infinity, 200000, 3);
}

TEST(MediaHomogeneous, ThroughputSteersTheChannelNotTheMean) {
    // Channel probabilities proportional to the path throughput (one channel nearly dead).
    check_medium(Color3(1.f, 0.2f, 3.f), Color3(0.5f, 0.9f, 0.99f), 1.5f, 200000, 4, Color3(0.05f, 1.f, 4.f));
    check_medium(Color3(0.f, 0.7f, 2.f), Color3(0.3f), Infinity, 200000, 5, Color3(2.f, 0.5f, 1.f));
}

TEST(MediaHomogeneous, AlbedoOneKeepsTheThroughputAverage) {
    // With albedo 1 the throughput-proportional choice conserves the channel average of the path
    // throughput exactly, at a scattering event and on escape: weights cannot build a heavy tail
    // over long walks (a uniform choice multiplies factors up to 3 per event).
    auto m = make_medium(Color3(2.f, 1.f, 3.f), Color3(1.f));
    const Ray ray(Point3f(0.f), Vec3f(0.f, 0.f, 1.f));
    const Color3 throughput(0.3f, 1.7f, 0.9f);
    for (int i = 0; i < 2000; ++i) {
        Sampler sampler(6, 0, uint64_t(i));
        FreeFlightSample fs = m->sample_free_flight(ray, 0.8f, throughput, sampler);
        EXPECT_NEAR((throughput * fs.weight).average(), throughput.average(), 1e-5f) << "sample " << i;
    }
}

TEST(MediaHomogeneous, GreyIsAnalog) {
    auto m = make_medium(Color3(2.f), Color3(0.8f, 0.6f, 0.4f));
    const Ray ray(Point3f(0.f), Vec3f(0.f, 0.f, 1.f));
    int scattered = 0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        Sampler sampler(4, 0, uint64_t(i));
        FreeFlightSample fs = m->sample_free_flight(ray, 1.f, Color3(0.2f, 1.f, 3.f), sampler);
        if (fs.scattered) {
            ++scattered;
            EXPECT_EQ(fs.weight, Color3(0.8f, 0.6f, 0.4f));
        } else {
            EXPECT_EQ(fs.weight, Color3(1.f));
        }
    }
    const double p = -std::expm1(-2.0);
    EXPECT_NEAR(double(scattered) / n, p, 4.5 * std::sqrt(p * (1 - p) / n));
}

TEST(MediaHomogeneous, ExactTransmittance) {
    auto m = make_medium(Color3(1.f, 0.f, 3.f), Color3(0.5f));
    Sampler s(1, 0, 0);
    const Color3 tr = m->transmittance(Ray(Point3f(0.f), Vec3f(1.f, 0.f, 0.f)), 0.5f, s);
    EXPECT_FLOAT_EQ(tr.r, std::exp(-0.5f));
    EXPECT_FLOAT_EQ(tr.g, 1.f);
    EXPECT_FLOAT_EQ(tr.b, std::exp(-1.5f));
    const Color3 tinf = m->transmittance(Ray(Point3f(0.f), Vec3f(1.f, 0.f, 0.f)), Infinity, s);
    EXPECT_EQ(tinf, Color3(0.f, 1.f, 0.f));
    EXPECT_TRUE(m->is_homogeneous());
}

TEST(MediaHomogeneous, MajorantWalkIsOneSegmentAtTheLargestChannel) {
    // The walk hands over a Poisson process of rate max sigma_t on (0, tmax) with the true sigma_t:
    // ratio tracking over it, prod (1 - sigma_t / mu), is unbiased for exp(-sigma_t s) per channel.
    auto m = make_medium(Color3(0.5f, 1.f, 2.f), Color3(0.7f));
    EXPECT_FALSE(m->tracks_null_collisions());
    const Medium& medium = *m;
    const Ray ray(Point3f(0.f), Vec3f(0.f, 1.f, 0.f));
    const float s = 1.5f;
    RunningStats tr[3], count;
    for (int i = 0; i < 40000; ++i) {
        Sampler sampler(5, 0, uint64_t(i));
        Color3 w(1.f);
        int n = 0;
        float previous = 0.f;
        medium.sample_majorant_walk(ray, s, sampler, [&](const MajorantCollision& c) {
            EXPECT_GT(c.t, previous);
            EXPECT_LT(c.t, s);
            EXPECT_EQ(c.mu, 2.f);
            EXPECT_EQ(c.sigma_t, Color3(0.5f, 1.f, 2.f));
            previous = c.t;
            ++n;
            w *= Color3(1.f) - c.sigma_t * (1.f / c.mu);
            return true;
        });
        for (int c = 0; c < 3; ++c) tr[c].add(w[c]);
        count.add(n);
    }
    for (int c = 0; c < 3; ++c) {
        const double want = std::exp(-double(Color3(0.5f, 1.f, 2.f)[c]) * s);
        EXPECT_LT(tr[c].z(want, 1e-6), 4.0) << "channel " << c << ": " << tr[c].mean() << " vs " << want;
    }
    EXPECT_LT(count.z(2.0 * s), 4.0) << count.mean();  // Poisson mean mu s
    EXPECT_NEAR(m->albedo(Point3f(0.f)).g, 0.7f, 1e-6f);
}
