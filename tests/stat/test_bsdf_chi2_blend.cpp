// Chi-square tests of `blendbsdf` (issue 40) against its own pdf (oracles.md §8), with the weight
// check eval/pdf: two smooth BSDFs (the blend's pdf is (1 - w) p_0 + w p_1), and a smooth BSDF with
// a smooth conductor (the delta lobe, picked with probability w, in the harness's rest bin). Weights
// 0 and 1 select one BSDF alone.
#include <gtest/gtest.h>

#include "support/bsdf_helpers.h"

using namespace volguide;
using namespace volguide::test;

namespace {

ChiSquareOptions blend_chi2_options() {
    ChiSquareOptions opt;
    opt.test_count = 6;  // chi-square tests in this file (Sidak correction)
    return opt;
}

std::shared_ptr<BSDF> blend_of(double weight, const std::shared_ptr<BSDF>& a, const std::shared_ptr<BSDF>& b) {
    return make_bsdf("blendbsdf", {{"weight", weight}, {"", ObjectPtr(a)}, {"", ObjectPtr(b)}});
}

}  // namespace

TEST(BsdfChi2, BlendDiffuseAndRoughConductor) {
    auto diffuse = make_bsdf("diffuse", {{"reflectance", Color3(0.2f, 0.5f, 0.8f)}});
    auto rough = make_bsdf("roughconductor", {{"alpha", 0.2}, {"distribution", "ggx"}});
    for (double w : {0.3, 1.0})
        for (float c : {0.8f, 0.3f}) {
            if (w == 1.0 && c == 0.3f) continue;
            auto r = chi2_bsdf(*blend_of(w, diffuse, rough), local_si(dir(c)), blend_chi2_options());
            EXPECT_TRUE(r.passed) << "weight " << w << " cos_theta_i " << c << "\n" << r.report;
        }
}

TEST(BsdfChi2, BlendDiffuseAndSmoothConductor) {
    auto diffuse = make_bsdf("diffuse");
    auto mirror = make_bsdf("conductor");
    for (double w : {0.6, 0.0}) {
        auto r = chi2_bsdf(*blend_of(w, diffuse, mirror), local_si(dir(0.7f)), blend_chi2_options());
        EXPECT_TRUE(r.passed) << "weight " << w << "\n" << r.report;
    }
}

TEST(BsdfBlend, EvalPdfAndDeltaSampleAreTheBlend) {
    auto diffuse = make_bsdf("diffuse", {{"reflectance", Color3(0.5f)}});
    auto rough = make_bsdf("roughconductor", {{"alpha", 0.3}});
    auto blend = blend_of(0.25, diffuse, rough);
    const SurfaceInteraction si = local_si(dir(0.6f));
    const Vec3f wo = dir(0.5f, 3.0f);
    const BSDFContext ctx;
    EXPECT_NEAR(blend->eval(ctx, si, wo).g, 0.75f * diffuse->eval(ctx, si, wo).g + 0.25f * rough->eval(ctx, si, wo).g,
                1e-6f);
    EXPECT_NEAR(blend->pdf(ctx, si, wo), 0.75f * diffuse->pdf(ctx, si, wo) + 0.25f * rough->pdf(ctx, si, wo), 1e-6f);
    // A mirror picked with probability 0.4: its discrete pdf times 0.4, its weight unchanged.
    auto mirror = make_bsdf("conductor");
    auto with_mirror = blend_of(0.4, diffuse, mirror);
    auto [bs, weight] = with_mirror->sample(ctx, si, 0.1f, {0.5f, 0.5f});
    auto [bs_m, weight_m] = mirror->sample(ctx, si, 0.25f, {0.5f, 0.5f});
    EXPECT_TRUE(bs.sampled_flags & bsdf_flags::DeltaReflection);
    EXPECT_NEAR(bs.pdf, 0.4f * bs_m.pdf, 1e-6f);
    EXPECT_NEAR(weight.r, weight_m.r, 1e-6f);
}
