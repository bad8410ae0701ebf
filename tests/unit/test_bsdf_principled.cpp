// `principled` / `principledthin` (issue 40, docs/theory.md §18): parameters and their errors,
// which lobes a parameter switches on, a hand-computed value, reciprocity of the reflection lobes
// and the thin sheet's symmetry.
#include <gtest/gtest.h>

#include "support/bsdf_helpers.h"

using namespace volguide;
using namespace volguide::test;

namespace {

void principled_expect_error(const std::string& type, const std::vector<Param>& params, const std::string& fragment) {
    try {
        make_bsdf(type, params);
        ADD_FAILURE() << type << ": expected an input error mentioning '" << fragment << "'";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        EXPECT_EQ(e.location().file, "test.xml");
    }
}

SurfaceInteraction principled_si(const Vec3f& wi) {
    return local_si(wi);
}

}  // namespace

TEST(BsdfPrincipled, ParameterErrors) {
    principled_expect_error("principled", {{"eta", 1.5}, {"specular", 0.5}}, "either 'eta' or 'specular'");
    principled_expect_error("principled", {{"specular", -0.1}}, "'specular' must lie in [0, 12.5)");
    principled_expect_error("principled", {{"eta", 0.0}}, "'eta' must be positive");
    principled_expect_error("principled", {{"clearcoat_sampling_rate", -1.0}}, "'clearcoat_sampling_rate'");
    principled_expect_error("principled", {{"diff_trans", 0.5}}, "diff_trans");  // thin only
    principled_expect_error("principledthin", {{"metallic", 0.5}}, "metallic");  // principled only
}

// Mitsuba switches a lobe on when its parameter is given and is not the float 0.
TEST(BsdfPrincipled, GivenParametersSwitchLobesOn) {
    EXPECT_FALSE(make_bsdf("principled")->has(bsdf_flags::GlossyTransmission));
    EXPECT_FALSE(make_bsdf("principled", {{"spec_trans", 0.0}})->has(bsdf_flags::GlossyTransmission));
    EXPECT_TRUE(make_bsdf("principled", {{"spec_trans", 0.3}})->has(bsdf_flags::GlossyTransmission));
    EXPECT_TRUE(make_bsdf("principledthin", {{"spec_trans", 0.3}})->has(bsdf_flags::GlossyTransmission));
    // Without a transmission lobe nothing leaves the inside.
    auto opaque = make_bsdf("principled");
    const SurfaceInteraction inside = principled_si(dir(-0.7f));
    EXPECT_EQ(opaque->pdf(BSDFContext{}, inside, dir(-0.5f, 2.f)), 0.f);
    EXPECT_EQ(opaque->eval(BSDFContext{}, inside, dir(-0.5f, 2.f)), Color3(0.f));
    EXPECT_EQ(opaque->sample(BSDFContext{}, inside, 0.5f, {0.3f, 0.6f}).first.pdf, 0.f);
}

// Defaults (base_color 0.5, roughness 0.5, specular 0.5 -> eta 1.5) at normal incidence and exitance:
// the diffuse term is base_color/pi (no Schlick darkening, no retro-reflection at cos = 1) and the
// specular one F(0) D(n) / 4 with F(0) = 0.04 and D(n) = 1 / (pi alpha^2), alpha = 0.25.
TEST(BsdfPrincipled, DefaultsAtNormalIncidence) {
    auto bsdf = make_bsdf("principled");
    const Color3 f = bsdf->eval(BSDFContext{}, principled_si(Vec3f(0, 0, 1)), Vec3f(0, 0, 1));
    const float expected = 0.5f * InvPi + 0.04f / (4.f * Pi * 0.0625f);
    EXPECT_NEAR(f.r, expected, 1e-5f);
    EXPECT_NEAR(f.g, expected, 1e-5f);
}

// Every reflection lobe is reciprocal: f(wi, wo) |cos_i| = f(wo, wi) |cos_o| for eval() = f |cos_o|.
TEST(BsdfPrincipled, ReflectionIsReciprocal) {
    auto bsdf = make_bsdf("principled", {{"base_color", Color3(0.2f, 0.8f, 0.1f)},
                                         {"roughness", 0.3},
                                         {"anisotropic", 0.5},
                                         {"metallic", 0.4},
                                         {"clearcoat", 0.8},
                                         {"sheen", 0.7},
                                         {"sheen_tint", 0.5},
                                         {"spec_tint", 0.5},
                                         {"flatness", 0.5}});
    const Vec3f a = dir(0.8f, 0.3f), b = dir(0.35f, 2.6f);
    const Color3 ab = bsdf->eval(BSDFContext{}, principled_si(a), b) / b.z;
    const Color3 ba = bsdf->eval(BSDFContext{}, principled_si(b), a) / a.z;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(ab[c], ba[c], 1e-5f * std::max(1.f, ab[c]));
    EXPECT_GT(ab.g, 0.f);
}

// The thin sheet looks the same from both sides.
TEST(BsdfPrincipled, ThinSheetIsTwoSided) {
    auto bsdf = make_bsdf("principledthin", {{"base_color", Color3(0.7f, 0.1f, 0.1f)},
                                             {"roughness", 0.4},
                                             {"spec_trans", 0.5},
                                             {"diff_trans", 0.8},
                                             {"sheen", 0.5}});
    const Vec3f wi = dir(0.6f, 0.2f);
    for (const Vec3f& wo : {dir(0.5f, 2.f), dir(-0.55f, 3.3f), dir(-0.9f, 0.1f)}) {
        const Color3 front = bsdf->eval(BSDFContext{}, principled_si(wi), wo);
        const Color3 back = bsdf->eval(BSDFContext{}, principled_si(-wi), -wo);
        EXPECT_GT(front.r, 0.f);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(front[c], back[c], 1e-6f);
        EXPECT_NEAR(bsdf->pdf(BSDFContext{}, principled_si(wi), wo), bsdf->pdf(BSDFContext{}, principled_si(-wi), -wo),
                    1e-6f);
    }
}
