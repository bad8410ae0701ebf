// White furnace tests: the directional albedo E[weight] = integral of f |cos theta_o| must not
// exceed 1 for any BSDF with unit reflectances, and approaches 1 where the model loses no energy
// (smooth dielectrics in importance mode, nearly smooth perfect conductors). A z-test bounds the
// Monte Carlo error; the mean of the weights is compared with the integral of eval() by the
// chi-square harness's quadrature where the BSDF has no delta lobes.
#include <gtest/gtest.h>

#include <cmath>

#include "support/bsdf_helpers.h"
#include "volguide/render/bsdfs/fresnel.h"

using namespace volguide;
using namespace volguide::test;

namespace {

struct Albedo {
    double mean = 0, stderr_ = 0;
};

Albedo albedo(const BSDF& bsdf, const SurfaceInteraction& si, TransportMode mode = TransportMode::Importance,
              int n = 200000) {
    BSDFContext ctx;
    ctx.mode = mode;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        Sampler s(11, 0, uint64_t(i));
        float u1 = s.next_1d();
        Point2f u2 = s.next_2d();
        auto [bs, w] = bsdf.sample(ctx, si, u1, u2);
        double v = bs.pdf > 0 ? double(w.g) : 0.0;
        sum += v;
        sum2 += v * v;
    }
    Albedo a;
    a.mean = sum / n;
    a.stderr_ = std::sqrt(std::max(0.0, sum2 / n - a.mean * a.mean) / n);
    return a;
}

// 5-sigma upper bound must not exceed 1 (plus float rounding).
void expect_at_most_one(const Albedo& a, const std::string& what) {
    EXPECT_LE(a.mean - 5 * a.stderr_, 1.0 + 1e-5) << what << ": albedo " << a.mean << " +- " << a.stderr_;
}

}  // namespace

TEST(BsdfFurnace, NoModelCreatesEnergy) {
    const std::vector<std::pair<std::string, std::vector<Param>>> models = {
        {"diffuse", {{"reflectance", Color3(1.f)}}},
        {"roughconductor", {{"alpha", 0.5}}},
        {"roughconductor", {{"alpha", 0.1}, {"distribution", "ggx"}}},
        {"roughconductor", {{"alpha_u", 0.05}, {"alpha_v", 0.5}, {"distribution", "ggx"}}},
        {"roughdielectric", {{"alpha", 0.3}}},
        {"roughdielectric", {{"alpha", 0.6}, {"distribution", "ggx"}}},
        // A white plastic base reaches 1.001 through the fitted Fdr (see LosslessLimits).
        {"plastic", {{"diffuse_reflectance", Color3(0.95f)}}},
        {"roughplastic", {{"diffuse_reflectance", Color3(1.f)}, {"alpha", 0.2}}},
        {"thindielectric", {}},
        {"conductor", {}},
    };
    for (const auto& [type, params] : models) {
        auto bsdf = make_bsdf(type, params);
        for (float c : {0.95f, 0.5f, 0.1f})
            expect_at_most_one(albedo(*bsdf, local_si(dir(c))), type + " cos " + std::to_string(c));
        if (bsdf->has(bsdf_flags::Transmission))
            for (float c : {-0.9f, -0.3f})
                expect_at_most_one(albedo(*bsdf, local_si(dir(c))), type + " inside");
    }
}

TEST(BsdfFurnace, LosslessLimits) {
    // Diffuse white: exactly 1.
    auto diffuse = make_bsdf("diffuse", {{"reflectance", Color3(1.f)}});
    EXPECT_NEAR(albedo(*diffuse, local_si(dir(0.4f))).mean, 1.0, 1e-6);
    // Smooth dielectric in importance mode: R + T = 1.
    auto glass = make_bsdf("dielectric");
    EXPECT_NEAR(albedo(*glass, local_si(dir(0.7f))).mean, 1.0, 1e-6);
    // In radiance mode the transmitted part is divided by eta^2 when entering.
    const float eta = 1.5046f / 1.000277f, F = fresnel_dielectric(0.7f, eta).F;
    Albedo a = albedo(*glass, local_si(dir(0.7f)), TransportMode::Radiance);
    EXPECT_NEAR(a.mean, F + (1 - F) / (eta * eta), 5 * a.stderr_ + 1e-6);
    // Perfect mirror microfacets with small roughness lose almost nothing to Smith shadowing.
    for (std::string d : {"beckmann", "ggx"}) {
        auto metal = make_bsdf("roughconductor", {{"alpha", 0.05}, {"distribution", d}});
        for (float c : {0.9f, 0.5f}) {
            Albedo m = albedo(*metal, local_si(dir(c)));
            EXPECT_GT(m.mean, 0.99) << d << " cos " << c;
            EXPECT_LE(m.mean, 1.0 + 1e-5) << d;
        }
        // A nearly smooth rough dielectric conserves energy in importance mode.
        auto rough_glass = make_bsdf("roughdielectric", {{"alpha", 0.02}, {"distribution", d}});
        Albedo g = albedo(*rough_glass, local_si(dir(0.8f)));
        EXPECT_NEAR(g.mean, 1.0, 0.01) << d;
    }
    // Plastic with a white base: by reciprocity (1 - Fdr_ext) = eta^2 (1 - Fdr_int), so the total
    // albedo is 1 up to the accuracy of the fitted Fdr (< 1%).
    auto plastic = make_bsdf("plastic", {{"diffuse_reflectance", Color3(1.f)}});
    Albedo p = albedo(*plastic, local_si(dir(0.6f)));
    EXPECT_NEAR(p.mean, 1.0, 0.01);
}

TEST(BsdfFurnace, SampledAlbedoMatchesIntegratedEval) {
    // E[weight] must equal the integral of eval over the sphere (quadrature from the chi-square
    // harness with a constant "pdf" of eval).
    const std::vector<std::pair<std::string, std::vector<Param>>> models = {
        {"roughconductor", {{"alpha", 0.3}, {"material", "Al"}}},
        {"roughdielectric", {{"alpha", 0.4}, {"distribution", "ggx"}}},
        {"roughplastic", {{"alpha", 0.3}, {"diffuse_reflectance", Color3(0.5f)}}},
    };
    for (const auto& [type, params] : models) {
        auto bsdf = make_bsdf(type, params);
        SurfaceInteraction si = local_si(dir(0.6f));
        BSDFContext ctx;
        ctx.mode = TransportMode::Importance;
        ChiSquareOptions opt;
        opt.sample_count = 1;      // only the quadrature is used
        opt.abs_tolerance = 1e-8;  // absolute quadrature tolerance (divided by sample_count)
        auto q = chi2_test_sphere(
            [](Sampler&) {
                return ChiSquareSample{Vec3f(0, 0, 1), Color3(1.f), false};
            },
            [&](const Vec3f& wo) { return double(bsdf->eval(ctx, si, wo).g); }, opt);
        Albedo a = albedo(*bsdf, si);
        EXPECT_NEAR(a.mean, q.pdf_integral, 5 * a.stderr_ + 1e-3 * q.pdf_integral) << type;
    }
}
