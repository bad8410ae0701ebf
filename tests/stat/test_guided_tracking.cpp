// Guided null-collision tracking (media/majorant_tracking.h's guided_tracking over the medium's majorant
// walk, docs/theory.md §7.7 H2) is
// unbiased for any scatter probability that is positive where sigma_s is and below 1 where
// mu > sigma_t: against quadrature on the tracking tests' procedural cloud (oracles.md §4),
//   E[w 1{escaped}] = T_c(s),  E[w 1{scattered}] = int T_c sigma_s,c dt,  E[w 1{scattered} t] = int T_c sigma_s,c t dt,
// per channel, grey and chromatic, tight and 10x loose majorant, for
//  - an arbitrary P_s (the unguided one modulated along the ray),
//  - the guided P_s of guided_volpath (GuidedCollisionProbability) on a synthetic guiding field
//    that covers only part of the cloud (rays enter and leave it);
// (per-flight mixing; per-collision mixing only at the tight majorant: its weights are heavy-tailed);
// a P_s that is 0 over a stretch with sigma_s > 0 must fail the same z-tests (the tests can fail);
// with P_s = P_a (grey) the walk is delta tracking: weight = albedo at scatters, 1 on escape, and
// the same decisions as sample_free_flight from the same random numbers; P_s = 1 / 0 where the
// other branch carries nothing are exact and finite; a NaN P_s falls back to the unguided one; the
// guide is asked once per tentative collision, in order, with the true coefficients there and
// normalised channel weights; spectral tracking over the walk the medium hands out is its own free
// flight, bit for bit.
// z-tests use |z| < 4 (per-test alpha 6e-5).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <initializer_list>
#include <vector>

#include "support/media_test_util.h"
#include "support/running_stats.h"
#include "volguide/guiding/guided_collision.h"
#include "volguide/media/majorant_tracking.h"
#include "volguide/vmm/phase_vmm.h"

using namespace volguide;
using namespace volguide::test;

namespace {

constexpr double kGuidedZ = 4.0;
constexpr double kGuidedFloor = 1e-6;

using ScatterFn = std::function<float(const TentativeCollision&)>;

// Unguided, modulated by a factor in [0.5, 1.5] that varies along the ray, with a floor where sigma_s > 0.
float modulated(const TentativeCollision& c) {
    const float s = std::sin(7.f * c.t);
    const float floor = c.sigma_s.max_value() > 0.f ? 0.02f : 0.f;
    return std::min((0.5f + s * s) * unguided_scatter_probability(c) + floor, 0.97f);
}

// Radiance from +y (varying with x), brighter above y = 0.6, over a box that holds part of the cloud.
GuidingField synthetic_field() {
    const BBox3f box(Point3f(-1.6f, -0.4f, -0.5f), Point3f(0.3f, 1.4f, 0.7f));
    std::vector<RadianceSample> samples;
    for (int i = 0; i < 16000; ++i) {
        Sampler s(41, 0, uint64_t(i));
        const Vec3f e = box.extents();
        const Point3f p(box.lo.x + e.x * s.next_1d(), box.lo.y + e.y * s.next_1d(), box.lo.z + e.z * s.next_1d());
        const VmfLobe lobe(normalize(Vec3f(0.4f * std::sin(3.f * p.x), 1.f, 0.2f)), 12.f);
        const Color3 weight = Color3(1.f + p.x * p.x, 0.6f, 0.3f) * (p.y > 0.6f ? 2.f : 0.5f);
        samples.push_back({p, lobe.sample(s.next_2d()), weight});
    }
    GuidingFieldSettings settings;
    settings.tree.max_samples = 1000;
    settings.lobes = 4;
    return GuidingField::build(box, samples, settings);
}

struct Expectations {
    RunningStats scat[3], scat_t[3], esc[3];
};

// Runs n guided flights per ray and majorant scale and z-tests the three expectations per channel.
// Returns the largest |z| seen (for the can-fail test).
double check_unbiased(HeterogeneousMedium& m, const std::function<ScatterFn(const TestRay&)>& guide_for,
                      int n, uint64_t seed, bool expect_pass = true,
                      std::initializer_list<float> majorant_scales = {1.f, 10.f}, float max_weight = Infinity) {
    double worst = 0.0;
    const auto rays = test_rays();
    for (size_t ri = 0; ri < rays.size(); ++ri) {
        const TestRay& r = rays[ri];
        RayProfile prof(m, r.ray, profile_length(m, r));
        for (float ms : majorant_scales) {
            m.set_majorant_scale(ms);
            Expectations e;
            for (int i = 0; i < n; ++i) {
                Sampler s(seed + ri, uint64_t(ms), uint64_t(i));
                ScatterFn guide = guide_for(r);
                const FreeFlightSample fs = guided_tracking(m, r.ray, r.tmax, Color3(1.f), s, guide);
                EXPECT_TRUE(fs.weight.is_finite());
                EXPECT_LE(fs.weight.max_value(), max_weight);
                if (fs.scattered) {
                    EXPECT_LT(fs.t, r.tmax);
                    const MediumCoefficients ref = m.eval(fs.mi.p);
                    EXPECT_NEAR(fs.mi.coeffs.sigma_s.g, ref.sigma_s.g, 1e-4f);
                    for (int c = 0; c < 3; ++c)
                        EXPECT_NEAR(fs.weight[c], fs.flight_weight[c] * fs.mi.coeffs.sigma_s[c],
                                    1e-5f * std::abs(fs.weight[c]) + 1e-7f);
                } else {
                    EXPECT_EQ(fs.weight, fs.flight_weight);
                }
                for (int c = 0; c < 3; ++c) {
                    e.scat[c].add(fs.scattered ? fs.weight[c] : 0.0);
                    e.scat_t[c].add(fs.scattered ? fs.weight[c] * fs.t : 0.0);
                    e.esc[c].add(fs.scattered ? 0.0 : fs.weight[c]);
                }
            }
            for (int c = 0; c < 3; ++c) {
                const double want[3] = {prof.scatter_integral(c, [](double) { return 1.0; }),
                                        prof.scatter_integral(c, [](double t) { return t; }),
                                        std::exp(-prof.total_tau(c))};
                const RunningStats* got[3] = {&e.scat[c], &e.scat_t[c], &e.esc[c]};
                const char* what[3] = {"scatter", "scatter * t", "escape"};
                for (int k = 0; k < 3; ++k) {
                    const double z = got[k]->z(want[k], kGuidedFloor);
                    worst = std::max(worst, z);
                    if (expect_pass) {
                        EXPECT_LT(z, kGuidedZ) << "ray " << ri << " majorant x" << ms << " channel " << c << " " << what[k]
                                         << ": " << got[k]->mean() << " vs " << want[k];
                    }
                }
            }
        }
    }
    m.set_majorant_scale(1.f);
    return worst;
}

ScatterFn modulated_guide(const TestRay&) { return modulated; }

}  // namespace

TEST(GuidedTracking, ArbitraryProbabilityGrey) {
    auto m = cloud_medium(1, Color3(0.7f), 4.f);
    check_unbiased(*m, modulated_guide, 20000, 100);
}

TEST(GuidedTracking, ArbitraryProbabilityChromatic) {
    auto m = cloud_medium(3, Color3(0.9f, 0.5f, 0.99f), 4.f);
    check_unbiased(*m, modulated_guide, 20000, 200);
}

static void check_field_guided(CollisionMixture mixture) {
    const GuidingField field = synthetic_field();
    ASSERT_GT(field.leaves().size(), 8u);
    const InscatterCache inscatter(field, hg_phase_vmm(0.f));
    const LeafEstimates estimates(field, inscatter, 0);  // exact
    for (int channels : {1, 3}) {
        SCOPED_TRACE(channels == 1 ? "grey" : "chromatic");
        auto m = cloud_medium(channels, channels == 1 ? Color3(0.8f) : Color3(0.9f, 0.5f, 0.99f), 4.f);
        uint64_t guided = 0, collisions = 0;
        auto guide_for = [&](const TestRay& r) -> ScatterFn {
            float b0, b1;
            const float t_end = field.tree().bounds().ray_intersect(r.ray, b0, b1) ? std::min(r.tmax, b1) : 0.f;
            auto p = std::make_shared<GuidedCollisionProbability>(field, &estimates, r.ray, t_end, 0.3f, mixture);
            return [p, &guided, &collisions](const TentativeCollision& c) {
                const uint64_t before = p->unguided_collisions();
                const float ps = p->scatter_probability(c);
                ++collisions;
                guided += p->unguided_collisions() == before;
                return ps;
            };
        };
        // Per flight, grey: at most the unguided weight (albedo or 1) / c_T. Per collision the factors
        // compound (heavy tails where the field says nothing comes from ahead): tight majorant only.
        const bool per_flight = mixture == CollisionMixture::PerFlight;
        check_unbiased(*m, guide_for, 20000, 300 + channels, true,
                       per_flight ? std::initializer_list<float>{1.f, 10.f} : std::initializer_list<float>{1.f},
                       per_flight && channels == 1 ? 1.0001f / 0.3f : Infinity);
        // Both guided and unguided (outside the field) collisions happened.
        EXPECT_GT(guided, collisions / 5);
        EXPECT_LT(guided, collisions);
    }
}

TEST(GuidedTracking, FieldGuidedProbabilityPerFlightMixture) { check_field_guided(CollisionMixture::PerFlight); }
TEST(GuidedTracking, FieldGuidedProbabilityPerCollisionMixture) { check_field_guided(CollisionMixture::PerCollision); }

TEST(GuidedTracking, AHoleInTheScatterProbabilityFails) {
    // P_s = 0 over a stretch of each ray where sigma_s > 0: that scattering mass is missing.
    auto m = cloud_medium(1, Color3(0.7f), 4.f);
    auto hole = [](const TestRay&) -> ScatterFn {
        return [](const TentativeCollision& c) {
            const float ps = modulated(c);
            return std::sin(7.f * c.t) > 0.7f ? 0.f : ps;
        };
    };
    EXPECT_GT(check_unbiased(*m, hole, 20000, 100, /*expect_pass=*/false), 2.0 * kGuidedZ);
}

TEST(GuidedTracking, AnalogProbabilityIsDeltaTracking) {
    auto m = cloud_medium(1, Color3(0.7f), 4.f);
    ScatterFn unguided = unguided_scatter_probability;
    int same = 0, total = 0, scattered = 0;
    for (const TestRay& r : test_rays())
        for (float ms : {1.f, 10.f}) {
            m->set_majorant_scale(ms);
            for (int i = 0; i < 5000; ++i) {
                Sampler s(7, uint64_t(ms), uint64_t(i)), s_ref(7, uint64_t(ms), uint64_t(i));
                TrackingCounts counts;
                const FreeFlightSample fs = guided_tracking(*m, r.ray, r.tmax, Color3(1.f), s, unguided, &counts);
                const FreeFlightSample ref = m->sample_free_flight(r.ray, r.tmax, Color3(1.f), s_ref);
                ASSERT_EQ(counts.real_collisions, fs.scattered ? 1u : 0u);
                const float expected = fs.scattered ? 0.7f : 1.f;
                for (int c = 0; c < 3; ++c) ASSERT_NEAR(fs.weight[c], expected, 1e-4f) << "sample " << i;
                ++total;
                scattered += fs.scattered;
                same += fs.scattered == ref.scattered && fs.t == ref.t;
            }
        }
    m->set_majorant_scale(1.f);
    EXPECT_GT(scattered, total / 5);
    EXPECT_GE(same, total - total / 1000);  // float rounding of the decision may differ, rarely
}

TEST(GuidedTracking, CertainDecisionsAreExactAndFinite) {
    // Constant sigma_t = majorant: sigma_n = 0, so P_s = 1 is allowed (every collision scatters,
    // weight = albedo); zero albedo: sigma_s = 0, so P_s = 0 is allowed (ratio tracking).
    auto constant = [](const Color3& albedo) {
        auto sigma = std::make_shared<Volume>(VoxelGrid(Color3(1.f)), Transform::scale(Vec3f(2.f)));
        auto alb = std::make_shared<Volume>(VoxelGrid(albedo), Transform());
        return std::make_shared<HeterogeneousMedium>(sigma, 1.5f, alb, std::make_shared<IsotropicPhase>());
    };
    const Ray ray(Point3f(0.1f, 1.f, 1.f), Vec3f(1.f, 0.f, 0.f));  // 1.9 inside the box
    const double transmittance = std::exp(-1.5 * 1.9);
    auto dense = constant(Color3(0.6f, 0.3f, 0.9f));
    ScatterFn always = [](const TentativeCollision&) { return 1.f; };
    RunningStats escaped;
    for (int i = 0; i < 20000; ++i) {
        Sampler s(11, 0, uint64_t(i));
        const FreeFlightSample fs = guided_tracking(*dense, ray, Infinity, Color3(1.f), s, always);
        ASSERT_TRUE(fs.weight.is_finite());
        if (fs.scattered) {
            ASSERT_NEAR(fs.weight.r, 0.6f, 1e-5f);
            ASSERT_NEAR(fs.weight.b, 0.9f, 1e-5f);
        } else {
            ASSERT_EQ(fs.weight, Color3(1.f));
        }
        escaped.add(fs.scattered ? 0.0 : 1.0);
    }
    EXPECT_LT(escaped.z(transmittance), kGuidedZ) << escaped.mean() << " vs " << transmittance;

    auto black = constant(Color3(0.f));
    ScatterFn never = [](const TentativeCollision&) { return 0.f; };
    ScatterFn nan = [](const TentativeCollision&) { return std::nanf(""); };
    for (ScatterFn* g : {&never, &nan}) {
        RunningStats tr;
        for (int i = 0; i < 20000; ++i) {
            Sampler s(12, 0, uint64_t(i));
            const FreeFlightSample fs = guided_tracking(*black, ray, Infinity, Color3(1.f), s, *g);
            ASSERT_FALSE(fs.scattered && g == &never);
            ASSERT_TRUE(fs.weight.is_finite());
            tr.add(fs.scattered ? 0.0 : fs.weight.r);
        }
        // sigma_t = majorant: the first null collision ends the walk with weight 0 (unbiased).
        EXPECT_LT(tr.z(transmittance, kGuidedFloor), kGuidedZ) << tr.mean() << " vs " << transmittance;
    }
}

TEST(GuidedTracking, TheGuideSeesEveryTentativeCollision) {
    auto m = cloud_medium(3, Color3(0.9f, 0.5f, 0.99f), 4.f);
    EXPECT_TRUE(m->tracks_null_collisions());
    struct Recording {
        std::vector<TentativeCollision> seen;
        float operator()(const TentativeCollision& c) {
            seen.push_back(c);
            return modulated(c);
        }
    };
    uint64_t collisions = 0, scattered = 0;
    for (const TestRay& r : test_rays())
        for (float ms : {1.f, 10.f}) {
            m->set_majorant_scale(ms);
            for (int i = 0; i < 500; ++i) {
                Sampler s(13, uint64_t(ms), uint64_t(i));
                Recording guide;
                TrackingCounts counts;
                const Medium& medium = *m;  // the virtual walk the walk guide calls
                const FreeFlightSample fs = guided_tracking(medium, r.ray, r.tmax, Color3(0.3f, 1.f, 0.6f), s, guide);
                // the same call with counters (and the same random numbers)
                Sampler s_counted(13, uint64_t(ms), uint64_t(i));
                Recording counted_guide;
                const FreeFlightSample fs_counted =
                    guided_tracking(medium, r.ray, r.tmax, Color3(0.3f, 1.f, 0.6f), s_counted, counted_guide, &counts);
                ASSERT_EQ(fs.t, fs_counted.t);
                ASSERT_EQ(fs.weight, fs_counted.weight);
                ASSERT_EQ(guide.seen.size(), counts.null_collisions + counts.real_collisions);
                ASSERT_EQ(counts.real_collisions, fs.scattered ? 1u : 0u);
                float previous = 0.f;
                for (const TentativeCollision& c : guide.seen) {
                    ASSERT_GT(c.t, previous);
                    ASSERT_LT(c.t, r.tmax);
                    previous = c.t;
                    const MediumCoefficients truth = m->eval(r.ray(c.t));
                    for (int ch = 0; ch < 3; ++ch) {
                        ASSERT_NEAR(c.sigma_t[ch], truth.sigma_t[ch], 1e-4f);  // world vs local lookup rounding
                        ASSERT_NEAR(c.sigma_s[ch], truth.sigma_s[ch], 1e-4f);
                        ASSERT_GE(c.sigma_t[ch], 0.f);
                        ASSERT_LE(c.sigma_t[ch], c.mu * (1.f + 1e-5f));
                        ASSERT_GE(c.channel_weights[ch], 0.f);
                    }
                    ASSERT_NEAR(c.channel_weights.r + c.channel_weights.g + c.channel_weights.b, 1.f, 1e-5f);
                }
                if (fs.scattered) {
                    ASSERT_FALSE(guide.seen.empty());
                    ASSERT_EQ(guide.seen.back().t, fs.t);
                }
                collisions += guide.seen.size();
                scattered += fs.scattered;
            }
        }
    m->set_majorant_scale(1.f);
    EXPECT_GT(scattered, 100u);
    EXPECT_GT(collisions, 10 * scattered);  // the loose majorant adds many nulls
}

TEST(GuidedTracking, SpectralTrackingOverTheHandedWalkIsTheFreeFlight) {
    // The walk Medium::sample_majorant_walk hands out is the one the medium's own free flight inlines:
    // spectral tracking as its callback gives the same flights from the same random numbers.
    auto m = cloud_medium(3, Color3(0.9f, 0.5f, 0.99f), 4.f);
    const Medium& medium = *m;
    int scattered = 0, total = 0;
    for (const TestRay& r : test_rays())
        for (float ms : {1.f, 10.f}) {
            m->set_majorant_scale(ms);
            for (int i = 0; i < 2000; ++i) {
                const Color3 throughput(0.3f, 1.f, 0.6f);
                Sampler s(17, uint64_t(ms), uint64_t(i)), s_ref(17, uint64_t(ms), uint64_t(i));
                const FreeFlightSample fs = track_collisions(
                    medium, r.ray, r.tmax, throughput, s, SpectralTrackingPolicy{}, nullptr,
                    [&](auto&& collide) { medium.sample_majorant_walk(r.ray, r.tmax, s, collide); });
                const FreeFlightSample ref = medium.sample_free_flight(r.ray, r.tmax, throughput, s_ref);
                ASSERT_EQ(fs.scattered, ref.scattered);
                ASSERT_EQ(fs.t, ref.t);
                ASSERT_EQ(fs.weight, ref.weight);
                ASSERT_EQ(fs.flight_weight, ref.flight_weight);
                ASSERT_EQ(s.next_1d(), s_ref.next_1d());  // the same random numbers consumed
                scattered += fs.scattered;
                ++total;
            }
        }
    m->set_majorant_scale(1.f);
    EXPECT_GT(scattered, total / 10);
    EXPECT_LT(scattered, total);
}
