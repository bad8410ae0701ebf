// The bitmap's eval_1_grad (bump mapping, issue 40): the derivative of the bilinear interpolation of
// the luminance with respect to uv, checked against central finite differences of eval_1 inside
// texel cells (through a to_uv scale, which enters through its transpose), zero for `nearest`.
#include <gtest/gtest.h>

#include "volguide/render/textures/textures.h"

using namespace volguide;

namespace {

Image test_image() {
    Image img(5, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 5; ++x) img.at(x, y) = Color3(0.1f * float(x * x) + 0.07f * float(y), 0.3f * float(y), 0.05f * float(x));
    return img;
}

SurfaceInteraction gradient_at(float u, float v) {
    SurfaceInteraction si;
    si.uv = Vec2f(u, v);
    return si;
}

TEST(BitmapGradient, MatchesFiniteDifferences) {
    UvTransform to_uv;
    to_uv.m[0][0] = 1.5f;  // u scaled: the u-derivative is 1.5 times the texel-space one
    BitmapTexture tex(test_image(), BitmapFilter::Bilinear, BitmapWrap::Repeat, to_uv);
    ASSERT_TRUE(tex.has_gradient());
    const float h = 1e-3f;
    for (Vec2f uv : {Vec2f(0.31f, 0.4f), Vec2f(0.52f, 0.83f), Vec2f(0.13f, 0.61f)}) {
        const Vec2f g = tex.eval_1_grad(gradient_at(uv.x, uv.y));
        const float du = (tex.eval_1(gradient_at(uv.x + h, uv.y)) - tex.eval_1(gradient_at(uv.x - h, uv.y))) / (2.f * h);
        const float dv = (tex.eval_1(gradient_at(uv.x, uv.y + h)) - tex.eval_1(gradient_at(uv.x, uv.y - h))) / (2.f * h);
        EXPECT_NEAR(g.x, du, 2e-2f * std::max(1.f, std::abs(du))) << uv.x << " " << uv.y;
        EXPECT_NEAR(g.y, dv, 2e-2f * std::max(1.f, std::abs(dv))) << uv.x << " " << uv.y;
    }
    BitmapTexture nearest(test_image(), BitmapFilter::Nearest, BitmapWrap::Repeat, UvTransform{});
    EXPECT_EQ(nearest.eval_1_grad(gradient_at(0.3f, 0.4f)), Vec2f(0.f, 0.f));
}

}  // namespace
