// Every BSDF returns finite, non-negative values for extreme inputs: grazing and normal
// incidence, samples at 0 and just below 1, directions on the horizon.
#include <gtest/gtest.h>

#include "support/bsdf_helpers.h"

using namespace volguide;
using namespace volguide::test;

TEST(BsdfRobustness, FiniteAndNonNegativeEverywhere) {
    const std::vector<std::pair<std::string, std::vector<Param>>> models = {
        {"diffuse", {}},
        {"dielectric", {}},
        {"thindielectric", {}},
        {"roughdielectric", {{"alpha", 0.01}}},
        {"roughdielectric", {{"alpha", 0.9}, {"distribution", "ggx"}}},
        {"roughdielectric", {{"alpha", 0.3}, {"sample_visible", false}}},
        {"conductor", {{"material", "Au"}}},
        {"roughconductor", {{"alpha", 0.001}}},
        {"roughconductor", {{"alpha_u", 0.9}, {"alpha_v", 0.05}, {"distribution", "ggx"}}},
        {"roughconductor", {{"alpha", 0.4}, {"sample_visible", false}}},
        {"plastic", {}},
        {"roughplastic", {{"alpha", 0.05}}},
        {"null", {}},
        {"principled", {{"roughness", 0.0}, {"metallic", 0.5}, {"clearcoat", 1.0}, {"clearcoat_gloss", 1.0},
                        {"sheen", 1.0}, {"sheen_tint", 1.0}, {"spec_tint", 1.0}, {"flatness", 1.0}}},
        {"principled", {{"roughness", 0.9}, {"spec_trans", 0.8}, {"anisotropic", 1.0}, {"eta", 1.0}}},
        {"principledthin", {{"roughness", 0.01}, {"spec_trans", 0.6}, {"diff_trans", 2.0}, {"sheen", 1.0},
                            {"spec_tint", 1.0}, {"eta", 1.0}}},
        {"blendbsdf", {{"weight", 0.3}, {"", ObjectPtr(make_bsdf("roughdielectric", {{"alpha", 0.2}}))},
                       {"", ObjectPtr(make_bsdf("conductor"))}}},
        {"blendbsdf", {{"weight", 1.0}, {"", ObjectPtr(make_bsdf("diffuse"))}, {"", ObjectPtr(make_bsdf("plastic"))}}},
        {"blendbsdf", {{"weight", 0.0}, {"", ObjectPtr(make_bsdf("diffuse"))}, {"", ObjectPtr(make_bsdf("null"))}}},
    };
    const float grazing = 1e-6f;
    const std::vector<Vec3f> wis = {Vec3f(0, 0, 1),
                                    Vec3f(0, 0, -1),
                                    normalize(Vec3f(1, 0, grazing)),
                                    normalize(Vec3f(0, 1, -grazing)),
                                    Vec3f(1, 0, 0),
                                    dir(0.5f),
                                    dir(-0.3f, 2.f)};
    const std::vector<float> us = {0.f, 0.5f, OneMinusEpsilon};
    for (const auto& [type, params] : models) {
        auto bsdf = make_bsdf(type, params);
        for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
            BSDFContext ctx;
            ctx.mode = mode;
            for (const Vec3f& wi : wis) {
                SurfaceInteraction si = local_si(wi);
                for (float u1 : us)
                    for (float ux : us)
                        for (float uy : us) {
                            auto [bs, w] = bsdf->sample(ctx, si, u1, {ux, uy});
                            ASSERT_TRUE(w.is_finite() && !w.has_negative())
                                << type << " wi " << wi << " w " << w;
                            ASSERT_TRUE(std::isfinite(bs.pdf) && bs.pdf >= 0.f) << type << " wi " << wi;
                            if (bs.pdf > 0.f && !w.is_black()) {
                                ASSERT_NEAR(norm(bs.wo), 1.f, 1e-3f)
                                    << type << " wi " << wi << " wo " << bs.wo;
                            }
                        }
                for (const Vec3f& wo : wis) {
                    Color3 f = bsdf->eval(ctx, si, wo);
                    float p = bsdf->pdf(ctx, si, wo);
                    ASSERT_TRUE(f.is_finite() && !f.has_negative()) << type << " wi " << wi << " wo " << wo;
                    ASSERT_TRUE(std::isfinite(p) && p >= 0.f) << type << " wi " << wi << " wo " << wo;
                }
            }
        }
    }
}
