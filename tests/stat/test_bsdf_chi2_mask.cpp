// Chi-square test of the `mask` BSDF (issue 40) against its own pdf (oracles.md §8): the nested
// lobes with probability opacity, the Null pass-through (the harness's rest bin) with 1 - opacity.
#include <gtest/gtest.h>

#include "support/bsdf_helpers.h"

using namespace volguide;
using namespace volguide::test;

namespace {

ChiSquareOptions options() {
    ChiSquareOptions opt;
    opt.test_count = 2;  // chi-square tests in this file (Sidak correction)
    return opt;
}

}  // namespace

TEST(BsdfChi2, MaskOverRoughConductor) {
    auto rough = make_bsdf("roughconductor", {{"alpha", 0.3}, {"distribution", "ggx"}});
    auto mask = make_bsdf("mask", {{"opacity", Color3(0.3f)}, {"", ObjectPtr(rough)}});
    for (float c : {0.8f, 0.3f}) {
        auto r = chi2_bsdf(*mask, local_si(dir(c)), options());
        EXPECT_TRUE(r.passed) << "cos_theta_i " << c << "\n" << r.report;
    }
}

TEST(BsdfMask, NullLobeAndOpacity) {
    auto diffuse = make_bsdf("diffuse", {{"reflectance", Color3(0.5f)}});
    auto mask = make_bsdf("mask", {{"opacity", Color3(0.25f)}, {"", ObjectPtr(diffuse)}});
    const SurfaceInteraction si = local_si(dir(0.6f));
    EXPECT_FLOAT_EQ(mask->eval_null_transmission(si).r, 0.75f);
    auto [bs, w] = mask->sample(BSDFContext{}, si, 0.9f, {0.3f, 0.3f});  // 0.9 >= opacity: passes through
    EXPECT_EQ(bs.sampled_flags, uint32_t(bsdf_flags::Null));
    EXPECT_FLOAT_EQ(bs.pdf, 0.75f);
    EXPECT_EQ(w, Color3(1.f));
    EXPECT_FLOAT_EQ(bs.wo.z, -si.wi.z);
    const Vec3f wo = dir(0.7f, 2.f);
    EXPECT_FLOAT_EQ(mask->eval(BSDFContext{}, si, wo).r, 0.25f * diffuse->eval(BSDFContext{}, si, wo).r);
    EXPECT_FLOAT_EQ(mask->pdf(BSDFContext{}, si, wo), 0.25f * diffuse->pdf(BSDFContext{}, si, wo));
}
