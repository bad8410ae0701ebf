// Chi-square tests of `principled` and `principledthin` (issue 40; docs/theory.md §18) against their
// own pdf, with the harness's weight check (sample() weight == eval / pdf): every lobe switched on,
// isotropic and anisotropic, outside and inside the object (principled's transmission lobe), both
// sides of the thin sheet, both transport modes.
#include <gtest/gtest.h>

#include "support/bsdf_helpers.h"

using namespace volguide;
using namespace volguide::test;

namespace {

ChiSquareOptions principled_chi2_options() {
    ChiSquareOptions opt;
    opt.test_count = 12;  // chi-square tests in this file (Sidak correction)
    return opt;
}

std::vector<Param> principled_chi2_opaque() {
    return {{"base_color", Color3(0.2f, 0.8f, 0.1f)},
            {"roughness", 0.4},
            {"metallic", 0.3},
            {"clearcoat", 0.6},
            {"clearcoat_gloss", 0.3},
            {"sheen", 0.5},
            {"sheen_tint", 0.4},
            {"spec_tint", 0.5},
            {"flatness", 0.3},
            {"specular", 0.7}};
}

}  // namespace

TEST(BsdfChi2, PrincipledOpaqueAllLobes) {
    auto bsdf = make_bsdf("principled", principled_chi2_opaque());
    for (float c : {0.8f, 0.25f}) {
        auto r = chi2_bsdf(*bsdf, local_si(dir(c)), principled_chi2_options());
        EXPECT_TRUE(r.passed) << "cos_theta_i " << c << "\n" << r.report;
    }
}

TEST(BsdfChi2, PrincipledAnisotropicLowRoughness) {
    auto params = principled_chi2_opaque();
    params.push_back({"anisotropic", 0.7});
    params[1] = {"roughness", 0.15};  // the suite scenes' value
    auto bsdf = make_bsdf("principled", params);
    auto r = chi2_bsdf(*bsdf, local_si(dir(0.6f, 1.1f)), principled_chi2_options());
    EXPECT_TRUE(r.passed) << r.report;
}

// With spec_trans the specular lobe splits by the microfacet's Fresnel into reflection and
// refraction; from inside only those two lobes exist.
TEST(BsdfChi2, PrincipledTransmissionBothSides) {
    auto bsdf = make_bsdf("principled", {{"base_color", Color3(0.3f, 0.6f, 0.8f)},
                                         {"roughness", 0.35},
                                         {"spec_trans", 0.6},
                                         {"metallic", 0.1},
                                         {"clearcoat", 0.4},
                                         {"sheen", 0.5},
                                         {"eta", 1.4}});
    for (float c : {0.7f, -0.6f, -0.2f}) {
        auto r = chi2_bsdf(*bsdf, local_si(dir(c)), principled_chi2_options());
        EXPECT_TRUE(r.passed) << "cos_theta_i " << c << "\n" << r.report;
    }
    auto r = chi2_bsdf(*bsdf, local_si(dir(-0.6f)), principled_chi2_options(), TransportMode::Importance);
    EXPECT_TRUE(r.passed) << "importance\n" << r.report;
}

TEST(BsdfChi2, PrincipledThinAllLobes) {
    auto bsdf = make_bsdf("principledthin", {{"base_color", Color3(0.7f, 0.1f, 0.1f)},
                                             {"roughness", 0.3},
                                             {"anisotropic", 0.5},
                                             {"spec_trans", 0.5},
                                             {"diff_trans", 0.8},
                                             {"sheen", 0.6},
                                             {"sheen_tint", 0.5},
                                             {"spec_tint", 0.3},
                                             {"flatness", 0.4},
                                             {"eta", 1.33}});
    for (float c : {0.75f, 0.2f, -0.5f}) {
        auto r = chi2_bsdf(*bsdf, local_si(dir(c, 0.9f)), principled_chi2_options());
        EXPECT_TRUE(r.passed) << "cos_theta_i " << c << "\n" << r.report;
    }
}

// Without spec_trans the thin sheet is diffuse only (its specular lobes are spec_trans-weighted).
TEST(BsdfChi2, PrincipledThinDiffuseOnly) {
    auto bsdf = make_bsdf("principledthin", {{"base_color", Color3(0.5f)}, {"diff_trans", 1.4}});
    for (float c : {0.6f, -0.9f}) {
        auto r = chi2_bsdf(*bsdf, local_si(dir(c)), principled_chi2_options());
        EXPECT_TRUE(r.passed) << "cos_theta_i " << c << "\n" << r.report;
    }
}
