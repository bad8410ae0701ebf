// Checkerboard texture: Mitsuba's pattern (color0 where both fractional uv coordinates are on the
// same side of 1/2), defaults, to_uv, the scalar-lookup convention, and the texture factory.
#include <gtest/gtest.h>

#include "support/bsdf_helpers.h"
#include "volguide/render/textures/textures.h"

using namespace volguide;
using namespace volguide::test;

namespace {

SurfaceInteraction at_uv(float u, float v) {
    SurfaceInteraction si;
    si.uv = Vec2f(u, v);
    return si;
}

}  // namespace

TEST(Checkerboard, DefaultsAndPattern) {
    auto tex = make_checkerboard_texture(make_props("texture", "checkerboard", {}));
    const Color3 c0(0.4f), c1(0.2f);
    EXPECT_EQ(tex->eval(at_uv(0.25f, 0.25f)), c0);
    EXPECT_EQ(tex->eval(at_uv(0.75f, 0.75f)), c0);
    EXPECT_EQ(tex->eval(at_uv(0.75f, 0.25f)), c1);
    EXPECT_EQ(tex->eval(at_uv(0.25f, 0.75f)), c1);
    // Periodic with period 1, also for negative coordinates (floor, not truncation).
    EXPECT_EQ(tex->eval(at_uv(1.25f, 3.25f)), c0);
    EXPECT_EQ(tex->eval(at_uv(-0.75f, 0.25f)), c0);
    EXPECT_EQ(tex->eval(at_uv(-0.25f, 0.25f)), c1);
    // Exactly 1/2 is not "> 1/2".
    EXPECT_EQ(tex->eval(at_uv(0.5f, 0.1f)), c0);
    EXPECT_NEAR(tex->mean().r, 0.3f, 1e-6f);
}

TEST(Checkerboard, ColorsAndToUv) {
    // As in Mitsuba's test scene: color0 0.2, color1 0.4, to_uv = scale 16.
    Matrix4 m = Matrix4::identity();
    m.m[0][0] = m.m[1][1] = m.m[2][2] = 16.0;
    auto tex = make_checkerboard_texture(make_props(
        "texture", "checkerboard",
        {{"color0", Color3(0.2f)}, {"color1", Color3(0.1f, 0.5f, 0.9f)}, {"to_uv", Transform(m)}}));
    EXPECT_EQ(tex->eval(at_uv(0.01f, 0.01f)), Color3(0.2f));
    EXPECT_EQ(tex->eval(at_uv(1.f / 32 + 0.01f, 0.01f)), Color3(0.1f, 0.5f, 0.9f));  // 16 * u = 0.66
    EXPECT_EQ(tex->eval(at_uv(1.f / 16 + 0.01f, 0.01f)), Color3(0.2f));
    // The translation column of a 4x4 to_uv (<translate>) shifts the lookup (Mitsuba 3's render test
    // texture_interp; releases before 3.6 ignored it).
    Matrix4 t = Matrix4::identity();
    t.m[0][3] = 0.5;
    auto shifted =
        make_checkerboard_texture(make_props("texture", "checkerboard", {{"to_uv", Transform(t)}}));
    EXPECT_EQ(shifted->eval(at_uv(0.25f, 0.25f)), Color3(0.2f));
    // ... but the third column (2-D translation of the 3x3 block) is applied.
    Matrix4 t2 = Matrix4::identity();
    t2.m[0][2] = 0.5;
    auto shifted2 =
        make_checkerboard_texture(make_props("texture", "checkerboard", {{"to_uv", Transform(t2)}}));
    EXPECT_EQ(shifted2->eval(at_uv(0.25f, 0.25f)), Color3(0.2f));
}

TEST(Checkerboard, ScalarLookupKeepsMitsubaConvention) {
    // Mitsuba's eval_1 swaps the colours relative to eval (kept for compatibility).
    auto tex = make_checkerboard_texture(make_props("texture", "checkerboard", {}));
    EXPECT_FLOAT_EQ(tex->eval_1(at_uv(0.25f, 0.25f)), 0.2f);
    EXPECT_FLOAT_EQ(tex->eval_1(at_uv(0.75f, 0.25f)), 0.4f);
}

TEST(Checkerboard, AsBsdfParameter) {
    auto tex = make_checkerboard_texture(make_props("texture", "checkerboard", {}));
    auto bsdf = make_bsdf("diffuse", {{"reflectance", ObjectPtr(tex)}});
    BSDFContext ctx;
    SurfaceInteraction si = local_si(Vec3f(0, 0, 1));
    si.uv = Vec2f(0.75f, 0.25f);
    EXPECT_NEAR(bsdf->eval(ctx, si, Vec3f(0, 0, 1)).r, 0.2f * InvPi, 1e-6f);
    si.uv = Vec2f(0.25f, 0.25f);
    EXPECT_NEAR(bsdf->sample(ctx, si, 0.5f, {0.5f, 0.5f}).second.g, 0.4f, 1e-6f);
}
