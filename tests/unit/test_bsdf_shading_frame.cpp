// The perturbed shading frame of `normalmap` / `bumpmap` (render/bsdfs/shading_frame_bsdf.h,
// docs/theory.md §20): Estevez et al.'s shadowing term against hand-computed values, and the flip of
// invalid normals on a constant normal map over a diffuse BSDF against the value computed by hand in
// the mirrored frame.
#include <gtest/gtest.h>

#include <cmath>

#include "support/bsdf_helpers.h"
#include "volguide/render/bsdfs/shading_frame_bsdf.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// A direction in the xz-plane with the given tan²(theta), z > 0.
Vec3f shading_frame_dir_tan2(float tan2) {
    return normalize(Vec3f(std::sqrt(tan2), 0.f, 1.f));
}

// normalmap with the constant normal n (rgb = (n + 1) / 2) over a white diffuse BSDF.
std::shared_ptr<BSDF> shading_frame_normalmap(const Vec3f& n, bool flip, bool shadowing) {
    auto diffuse = make_bsdf("diffuse", {{"reflectance", Color3(1.f)}});
    const Color3 rgb(0.5f * (n.x + 1.f), 0.5f * (n.y + 1.f), 0.5f * (n.z + 1.f));
    return make_bsdf("normalmap", {{"normalmap", rgb},
                                   {"flip_invalid_normals", flip},
                                   {"use_shadowing_function", shadowing},
                                   {"", ObjectPtr(diffuse)}});
}

}  // namespace

TEST(BsdfShadingFrame, ShadowTerminatorByHand) {
    // Unperturbed normal: no shadowing whatever the direction.
    EXPECT_EQ(ShadingFrameBSDF::shadow_terminator(Vec3f(0, 0, 1), shading_frame_dir_tan2(50.f)), 1.f);
    // tan²θ_n = 8 -> a² = min(8 / 8, 1) = 1; tan²θ_o = 3: G = 2 / (1 + sqrt(4)) = 2/3.
    EXPECT_NEAR(ShadingFrameBSDF::shadow_terminator(shading_frame_dir_tan2(8.f), shading_frame_dir_tan2(3.f)),
                2.f / 3.f, 1e-5f);
    // tan²θ_n = 0.8 -> a² = 0.1; tan²θ_o = 10: G = 2 / (1 + sqrt(2)).
    EXPECT_NEAR(
        ShadingFrameBSDF::shadow_terminator(shading_frame_dir_tan2(0.8f), shading_frame_dir_tan2(10.f)),
        2.f / (1.f + std::sqrt(2.f)), 1e-5f);
    // a² is capped at 1: tan²θ_n = 80 shadows as much as 8.
    EXPECT_NEAR(
        ShadingFrameBSDF::shadow_terminator(shading_frame_dir_tan2(80.f), shading_frame_dir_tan2(3.f)),
        2.f / 3.f, 1e-5f);
}

TEST(BsdfShadingFrame, InvalidNormalIsMirroredAboutTheShadingNormal) {
    const Vec3f n = normalize(Vec3f(0.4f, 0.f, 0.92f));  // tilted towards +x
    // wi comes from -x at a grazing angle: in front of the surface, behind the perturbed one.
    SurfaceInteraction si = local_si(Vec3f(-0.95f, 0.f, 0.31f));
    ASSERT_LT(dot(si.wi, n), 0.f);
    const Vec3f wo = normalize(Vec3f(0.2f, 0.3f, 0.9f));
    const BSDFContext ctx;

    // Without the flip the diffuse lobe sees wi below its surface: zero.
    EXPECT_EQ(shading_frame_normalmap(n, false, false)->eval(ctx, si, wo).r, 0.f);
    // With it the normal becomes (-n.x, -n.y, n.z): the diffuse value cos(wo, n') / pi.
    const Vec3f flipped(-n.x, -n.y, n.z);
    const float expected = std::max(0.f, dot(wo, flipped)) / float(M_PI);
    EXPECT_NEAR(shading_frame_normalmap(n, true, false)->eval(ctx, si, wo).r, expected, 1e-5f);
    // And the shadowing term multiplies the value, not the pdf.
    auto both = shading_frame_normalmap(n, true, true);
    EXPECT_NEAR(both->eval(ctx, si, wo).r, expected * ShadingFrameBSDF::shadow_terminator(flipped, wo),
                1e-5f);
    EXPECT_NEAR(both->pdf(ctx, si, wo), expected, 1e-5f);
    // A valid normal (wi from +x) is not flipped.
    const SurfaceInteraction front = local_si(Vec3f(0.6f, 0.f, 0.8f));
    EXPECT_NEAR(shading_frame_normalmap(n, true, false)->eval(ctx, front, wo).r, dot(wo, n) / float(M_PI),
                1e-5f);
}
