// Chi-square tests of the wrapping BSDFs of issue 40 against their own pdf (oracles.md §8): `mask` (the
// nested lobes with probability opacity, the Null pass-through in the harness's rest bin with
// 1 - opacity) and `normalmap` (the nested lobe in a tilted shading frame; directions below the
// unperturbed surface are dropped, their probability in the rest bin).
#include <gtest/gtest.h>

#include "support/bsdf_helpers.h"

using namespace volguide;
using namespace volguide::test;

namespace {

ChiSquareOptions options() {
    ChiSquareOptions opt;
    opt.test_count = 4;  // chi-square tests in this file (Sidak correction)
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

TEST(BsdfChi2, NormalMapOverRoughConductor) {
    auto rough = make_bsdf("roughconductor", {{"alpha", 0.3}, {"distribution", "ggx"}});
    // A constant normal map: the shading normal tilted by ~25 degrees towards +x.
    auto normalmap = make_bsdf("normalmap", {{"normalmap", Color3(0.7f, 0.5f, 0.93f)}, {"", ObjectPtr(rough)}});
    for (float c : {0.8f, 0.3f}) {
        SurfaceInteraction si = local_si(dir(c));
        si.dp_du = Vec3f(1, 0, 0);  // the tangent the normal map's frame is built from
        si.dp_dv = Vec3f(0, 1, 0);
        auto r = chi2_bsdf(*normalmap, si, options());
        EXPECT_TRUE(r.passed) << "cos_theta_i " << c << "\n" << r.report;
    }
}
