// Chi-square tests of BSDF sampling against the BSDF's own pdf (oracles.md §8) for the diffuse,
// plastic and twosided models. Delta lobes count towards the harness's rest bin, so the
// probability of choosing them is tested too.
#include <gtest/gtest.h>

#include "support/bsdf_helpers.h"

using namespace volguide;
using namespace volguide::test;

namespace {

constexpr int kBasicTests = 14;  // chi-square tests in this file (Sidak correction)

ChiSquareOptions basic_options() {
    ChiSquareOptions opt;
    opt.test_count = kBasicTests;
    return opt;
}

}  // namespace

TEST(BsdfChi2, Diffuse) {
    auto bsdf = make_bsdf("diffuse", {{"reflectance", Color3(0.2f, 0.5f, 0.8f)}});
    for (float c : {0.9f, 0.2f}) {
        auto r = chi2_bsdf(*bsdf, local_si(dir(c)), basic_options());
        EXPECT_TRUE(r.passed) << "cos_theta_i " << c << "\n" << r.report;
    }
}

TEST(BsdfChi2, PlasticDiffuseLobeAndSpecularProbability) {
    auto bsdf = make_bsdf("plastic", {{"diffuse_reflectance", Color3(0.3f, 0.5f, 0.1f)}, {"int_ior", 1.7}});
    for (float c : {0.95f, 0.3f, 0.05f}) {
        auto r = chi2_bsdf(*bsdf, local_si(dir(c)), basic_options());
        EXPECT_TRUE(r.passed) << "cos_theta_i " << c << "\n" << r.report;
        EXPECT_GT(r.rest_observed, 0u);  // the delta lobe is sampled
    }
}

TEST(BsdfChi2, RoughPlastic) {
    struct Case {
        std::string distr;
        double alpha;
        float cos_theta;
        bool nonlinear;
    };
    for (const Case& c : {Case{"beckmann", 0.1, 0.8f, false}, Case{"ggx", 0.3, 0.4f, true},
                          Case{"beckmann", 0.5, 0.15f, false}, Case{"ggx", 0.05, 0.9f, false}}) {
        auto bsdf = make_bsdf("roughplastic", {{"distribution", c.distr},
                                               {"alpha", c.alpha},
                                               {"nonlinear", c.nonlinear},
                                               {"diffuse_reflectance", Color3(0.6f, 0.2f, 0.4f)}});
        auto r = chi2_bsdf(*bsdf, local_si(dir(c.cos_theta)), basic_options());
        EXPECT_TRUE(r.passed) << c.distr << " alpha " << c.alpha << " cos " << c.cos_theta << "\n"
                              << r.report;
    }
}

TEST(BsdfChi2, RoughPlasticWithoutVisibleNormalSampling) {
    auto bsdf = make_bsdf("roughplastic", {{"alpha", 0.2}, {"sample_visible", false}});
    auto r = chi2_bsdf(*bsdf, local_si(dir(0.6f)), basic_options());
    EXPECT_TRUE(r.passed) << r.report;
}

TEST(BsdfChi2, TwoSidedBackSide) {
    // One nested BSDF: the back side mirrors it.
    auto diffuse = make_bsdf("diffuse", {{"reflectance", Color3(0.7f)}});
    auto two = make_bsdf("twosided", {{"", ObjectPtr(diffuse)}});
    auto r = chi2_bsdf(*two, local_si(dir(-0.5f)), basic_options());
    EXPECT_TRUE(r.passed) << r.report;

    // Two nested BSDFs: the back uses the second one.
    auto rough = make_bsdf("roughconductor", {{"alpha", 0.3}, {"distribution", "ggx"}});
    auto two2 = make_bsdf("twosided", {{"front", ObjectPtr(diffuse)}, {"back", ObjectPtr(rough)}});
    auto r2 = chi2_bsdf(*two2, local_si(dir(-0.7f)), basic_options());
    EXPECT_TRUE(r2.passed) << r2.report;
    auto r3 = chi2_bsdf(*two2, local_si(dir(0.7f)), basic_options());
    EXPECT_TRUE(r3.passed) << r3.report;
}
