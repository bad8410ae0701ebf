// HG and isotropic phase functions: oracles.md §6 identities (by quadrature of eval and by
// sampling), the direction convention (wi = -ray.d, g > 0 scatters forward), robustness near
// |g| = 1, and Mitsuba's parameter handling (g default 0.8, |g| >= 1 rejected at its line).
#include <gtest/gtest.h>

#include "volguide/core/frame.h"
#include "volguide/core/properties.h"
#include "volguide/core/sampler.h"
#include "volguide/media/phase_hg.h"
#include "volguide/media/phase_isotropic.h"
#include "volguide/scene/factories.h"

using namespace volguide;

namespace {

// Integrates f(mu) over the sphere in mu = cos(angle to the axis) with a fine midpoint rule
// refined towards mu = 1 and mu = -1 (where peaked lobes live).
template <typename F>
double integrate_mu(F f) {
    double sum = 0.0;
    const int n = 200000;
    // Substitution mu = 1 - 2 s^3-like stretching at both ends: mu = cos(pi x), dmu = pi sin(pi x) dx.
    for (int i = 0; i < n; ++i) {
        const double x = (i + 0.5) / n;
        const double mu = std::cos(M_PI * x);
        sum += f(mu) * M_PI * std::sin(M_PI * x) / n;
    }
    return 2.0 * M_PI * sum;
}

Vec3f dir_with_cos(const Vec3f& axis, double mu) {
    Frame fr(axis);
    const double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    return fr.to_world(Vec3f(float(s), 0.f, float(mu)));
}

}  // namespace

TEST(PhaseHG, IdentitiesByQuadrature) {
    const Vec3f d = normalize(Vec3f(0.3f, -0.5f, 0.8f));  // ray direction
    const Vec3f wi = -d;
    for (float g : {-0.9f, -0.5f, 0.f, 0.3f, 0.9f}) {
        HGPhase hg(g);
        auto p = [&](double mu) { return double(hg.eval(wi, dir_with_cos(d, mu))); };
        EXPECT_NEAR(integrate_mu(p), 1.0, 2e-3) << g;
        EXPECT_NEAR(integrate_mu([&](double mu) { return mu * p(mu); }), g, 2e-3) << g;
        EXPECT_NEAR(integrate_mu([&](double mu) { return mu * mu * p(mu); }), (1 + 2 * g * g) / 3, 2e-3) << g;
    }
}

TEST(PhaseHG, MomentsBySampling) {
    const Vec3f d = normalize(Vec3f(-0.2f, 0.9f, 0.1f));
    const int n = 400000;
    for (float g : {-0.99f, -0.9f, -0.5f, 0.f, 0.3f, 0.9f, 0.99f}) {
        HGPhase hg(g);
        double m1 = 0, m2 = 0;
        for (int i = 0; i < n; ++i) {
            Sampler s(3, 0, uint64_t(i));
            PhaseSample ps = hg.sample(-d, s.next_2d());
            ASSERT_TRUE(all_finite(ps.wo));
            ASSERT_EQ(ps.weight, 1.f);
            ASSERT_NEAR(norm(ps.wo), 1.f, 1e-5f);
            const double mu = dot(Vec3d(ps.wo), Vec3d(d));
            m1 += mu;
            m2 += mu * mu;
        }
        m1 /= n;
        m2 /= n;
        const double e2 = (1.0 + 2.0 * g * g) / 3.0;
        const double sd1 = std::sqrt(std::max(e2 - double(g) * g, 1e-12) / n);
        EXPECT_NEAR(m1, g, 5 * sd1 + 1e-6) << "g " << g;
        EXPECT_NEAR(m2, e2, 5.0 / std::sqrt(double(n)) * 0.5 + 1e-6) << "g " << g;
    }
}

TEST(PhaseHG, ForwardMeansAlongTheRay) {
    // Mitsuba's convention: wi = -ray.d; g > 0 sends wo close to ray.d = -wi.
    const Vec3f d(0.f, 0.f, 1.f);
    HGPhase fwd(0.95f), bwd(-0.95f);
    int fwd_front = 0, bwd_front = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        Sampler s(5, 0, uint64_t(i));
        Point2f u = s.next_2d();
        fwd_front += fwd.sample(-d, u).wo.z > 0.f;
        bwd_front += bwd.sample(-d, u).wo.z > 0.f;
    }
    EXPECT_GE(fwd_front, 10 * (n - fwd_front));  // oracles §6: >= 10x more on the correct side
    EXPECT_GE(n - bwd_front, 10 * bwd_front);
    EXPECT_GT(fwd.eval(-d, d), 100.f * fwd.eval(-d, -d));
    EXPECT_GT(bwd.eval(-d, -d), 100.f * bwd.eval(-d, d));
    EXPECT_FLOAT_EQ(fwd.mean_cosine(), 0.95f);
}

TEST(PhaseHG, NoNaNNearTheLimits) {
    const Vec3f d = normalize(Vec3f(1.f, 2.f, 3.f));
    for (float g : {-1.f, -0.999f, 0.999f, 1.f}) {
        HGPhase hg(g);
        for (int i = 0; i < 20000; ++i) {
            Sampler s(9, 0, uint64_t(i));
            PhaseSample ps = hg.sample(-d, s.next_2d());
            ASSERT_TRUE(all_finite(ps.wo)) << g;
            ASSERT_TRUE(std::isfinite(ps.pdf) && ps.pdf > 0.f) << g;
            ASSERT_TRUE(std::isfinite(hg.eval(-d, ps.wo))) << g;
        }
        EXPECT_TRUE(std::isfinite(hg.eval(-d, d)));
        EXPECT_TRUE(std::isfinite(hg.eval(-d, -d)));
        // The peak keeps its analytic value: (1 - g^2) / (4 pi (1 - |g|)^3).
        const double ga = std::min(std::abs(double(g)), double(HGPhase::kMaxAbsG));
        const double peak = (1 - ga * ga) / (4 * M_PI * std::pow(1 - ga, 3));
        EXPECT_NEAR(hg.eval(-d, g > 0 ? d : -d) / peak, 1.0, 2e-2) << g;
    }
}

TEST(PhaseIsotropic, Uniform) {
    IsotropicPhase iso;
    double m1 = 0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        Sampler s(1, 0, uint64_t(i));
        PhaseSample ps = iso.sample(Vec3f(0, 0, 1), s.next_2d());
        EXPECT_FLOAT_EQ(ps.pdf, 1.f / (4.f * Pi));
        EXPECT_EQ(ps.weight, 1.f);
        m1 += ps.wo.x;
    }
    EXPECT_NEAR(m1 / n, 0.0, 5 * std::sqrt(1.0 / 3.0 / n));
    EXPECT_EQ(iso.mean_cosine(), 0.f);
}

TEST(PhasePlugins, MitsubaParameters) {
    Properties props("phase", "hg", {"scene.xml", 3});
    auto obj = create_phase(props);
    auto hg = std::dynamic_pointer_cast<HGPhase>(obj);
    ASSERT_TRUE(hg);
    EXPECT_FLOAT_EQ(hg->g(), 0.8f);  // Mitsuba's default

    for (double bad : {1.0, -1.0, 1.5, std::nan("")}) {
        Properties p("phase", "hg", {"scene.xml", 3});
        p.set("g", "float", bad, {"scene.xml", 4});
        try {
            create_phase(p);
            FAIL() << "g = " << bad << " accepted";
        } catch (const InputError& e) {
            EXPECT_EQ(e.location().line, 4);
            EXPECT_NE(std::string(e.what()).find("scene.xml:4"), std::string::npos);
        }
    }
    Properties iso("phase", "isotropic", {"scene.xml", 7});
    EXPECT_TRUE(std::dynamic_pointer_cast<IsotropicPhase>(create_phase(iso)));
    Properties unknown("phase", "rayleigh", {"scene.xml", 8});
    EXPECT_THROW(create_phase(unknown), InputError);
}
