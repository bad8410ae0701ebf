// Discrete lobe probabilities of the BSDFs with delta lobes: the fraction of samples taking each
// lobe against its analytic probability (chi-square on counts), and the directions produced.
#include <gtest/gtest.h>

#include "support/bsdf_helpers.h"
#include "volguide/render/bsdfs/fresnel.h"

using namespace volguide;
using namespace volguide::test;

namespace {

constexpr int kDeltaTests = 9;

ChiSquareOptions delta_options() {
    ChiSquareOptions opt;
    opt.test_count = kDeltaTests;
    return opt;
}

// Counts samples per sampled lobe flag (in the order given) over n samples.
std::vector<uint64_t> count_lobes(const BSDF& bsdf, const SurfaceInteraction& si,
                                  const std::vector<uint32_t>& lobes, int n = 200000) {
    std::vector<uint64_t> counts(lobes.size(), 0);
    BSDFContext ctx;
    for (int i = 0; i < n; ++i) {
        Sampler s(3, 0, uint64_t(i));
        float u1 = s.next_1d();
        Point2f u2 = s.next_2d();
        auto [bs, w] = bsdf.sample(ctx, si, u1, u2);
        for (size_t k = 0; k < lobes.size(); ++k)
            if (bs.sampled_flags == lobes[k]) ++counts[k];
    }
    return counts;
}

}  // namespace

TEST(BsdfDeltaLobes, DielectricChoosesReflectionWithFresnelProbability) {
    auto bsdf = make_bsdf("dielectric", {{"int_ior", 1.5}, {"ext_ior", 1.0}});
    for (float c : {0.95f, 0.3f, -0.9f, -0.76f}) {  // -0.76: just inside the critical angle
        SurfaceInteraction si = local_si(dir(c));
        const double F = fresnel_dielectric(si.wi.z, 1.5f).F;
        auto counts = count_lobes(*bsdf, si, {bsdf_flags::DeltaReflection, bsdf_flags::DeltaTransmission});
        auto r = chi2_test_discrete(counts, {F, 1 - F}, delta_options());
        EXPECT_TRUE(r.passed) << "cos_i " << c << " F " << F << "\n" << r.report;
    }
    // Total internal reflection: always reflected.
    auto counts = count_lobes(*bsdf, local_si(dir(-0.5f)),
                              {bsdf_flags::DeltaReflection, bsdf_flags::DeltaTransmission});
    EXPECT_EQ(counts[1], 0u);
}

TEST(BsdfDeltaLobes, ThinDielectric) {
    auto bsdf = make_bsdf("thindielectric", {{"int_ior", 1.5}, {"ext_ior", 1.0}});
    for (float c : {0.9f, -0.2f}) {
        SurfaceInteraction si = local_si(dir(c));
        const double R = fresnel_dielectric(std::abs(c), 1.5f).F, Rp = 2 * R / (1 + R);
        auto counts = count_lobes(*bsdf, si, {bsdf_flags::DeltaReflection, bsdf_flags::Null});
        auto r = chi2_test_discrete(counts, {Rp, 1 - Rp}, delta_options());
        EXPECT_TRUE(r.passed) << "cos_i " << c << "\n" << r.report;
    }
}

TEST(BsdfDeltaLobes, PlasticSpecularProbability) {
    // Mitsuba's choice: F * w_s against (1 - F) * (1 - w_s), w_s = s_mean / (d_mean + s_mean).
    auto bsdf = make_bsdf(
        "plastic", {{"diffuse_reflectance", Color3(0.2f, 0.4f, 0.6f)}, {"int_ior", 1.5}, {"ext_ior", 1.0}});
    for (float c : {0.8f, 0.1f}) {
        SurfaceInteraction si = local_si(dir(c));
        const double F = fresnel_dielectric(c, 1.5f).F, ws = 1.0 / 1.4;
        const double ps = F * ws / (F * ws + (1 - F) * (1 - ws));
        auto counts = count_lobes(*bsdf, si, {bsdf_flags::DeltaReflection, bsdf_flags::DiffuseReflection});
        auto r = chi2_test_discrete(counts, {ps, 1 - ps}, delta_options());
        EXPECT_TRUE(r.passed) << "cos_i " << c << "\n" << r.report;
    }
}

TEST(BsdfDeltaLobes, RoughDielectricLobeFractionIsFresnelAtNormalIncidenceLimit) {
    // With nearly smooth microfacets the reflected fraction tends to the smooth Fresnel term.
    auto bsdf = make_bsdf("roughdielectric", {{"alpha", 0.0001}, {"int_ior", 1.5}, {"ext_ior", 1.0}});
    SurfaceInteraction si = local_si(dir(0.6f));
    const double F = fresnel_dielectric(0.6f, 1.5f).F;
    auto counts = count_lobes(*bsdf, si, {bsdf_flags::GlossyReflection, bsdf_flags::GlossyTransmission});
    auto r = chi2_test_discrete(counts, {F, 1 - F}, delta_options());
    EXPECT_TRUE(r.passed) << r.report;
}
