// Bitmap texture lookups on an in-memory image (file loading goes through read_image(), tested
// with the image I/O module): Mitsuba's uv -> pixel convention (v = 0 is the top row), nearest
// and bilinear filtering, and the wrap modes.
#include <gtest/gtest.h>

#include "volguide/render/textures/textures.h"

using namespace volguide;

namespace {

// 4 x 2 image whose red channel encodes x and green encodes y.
Image ramp() {
    Image img(4, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) img.at(x, y) = Color3(float(x), float(y), 1.f);
    return img;
}

Color3 lookup(const BitmapTexture& t, float u, float v) {
    SurfaceInteraction si;
    si.uv = Vec2f(u, v);
    return t.eval(si);
}

}  // namespace

TEST(Bitmap, NearestPixelConvention) {
    BitmapTexture t(ramp(), BitmapFilter::Nearest, BitmapWrap::Repeat, UvTransform{});
    EXPECT_EQ(lookup(t, 0.01f, 0.01f), Color3(0, 0, 1));  // first pixel of the top row
    EXPECT_EQ(lookup(t, 0.99f, 0.01f), Color3(3, 0, 1));
    EXPECT_EQ(lookup(t, 0.3f, 0.75f), Color3(1, 1, 1));   // v grows downwards
    EXPECT_EQ(lookup(t, 1.3f, -0.25f), Color3(1, 1, 1));  // repeat
}

TEST(Bitmap, BilinearBetweenPixelCentres) {
    BitmapTexture t(ramp(), BitmapFilter::Bilinear, BitmapWrap::Clamp, UvTransform{});
    // Pixel centres reproduce the pixels.
    Color3 c = lookup(t, 1.5f / 4, 0.25f);
    EXPECT_NEAR(c.r, 1.f, 1e-5f);
    EXPECT_NEAR(c.g, 0.f, 1e-5f);
    // Half way between centres (x: 1 and 2, y: rows 0 and 1).
    c = lookup(t, 2.f / 4, 0.5f);
    EXPECT_NEAR(c.r, 1.5f, 1e-5f);
    EXPECT_NEAR(c.g, 0.5f, 1e-5f);
    // Clamp at the border.
    c = lookup(t, 0.f, 0.f);
    EXPECT_NEAR(c.r, 0.f, 1e-5f);
    EXPECT_NEAR(c.g, 0.f, 1e-5f);
}

TEST(Bitmap, WrapModes) {
    // Just left of u = 0, bilinear mixes pixel 0 with the pixel "before" it.
    BitmapTexture rep(ramp(), BitmapFilter::Bilinear, BitmapWrap::Repeat, UvTransform{});
    BitmapTexture mir(ramp(), BitmapFilter::Bilinear, BitmapWrap::Mirror, UvTransform{});
    BitmapTexture cla(ramp(), BitmapFilter::Bilinear, BitmapWrap::Clamp, UvTransform{});
    EXPECT_NEAR(lookup(rep, 0.f, 0.25f).r, 1.5f, 1e-5f);  // (3 + 0) / 2
    EXPECT_NEAR(lookup(mir, 0.f, 0.25f).r, 0.f, 1e-5f);   // mirrored: (0 + 0) / 2
    EXPECT_NEAR(lookup(cla, 0.f, 0.25f).r, 0.f, 1e-5f);
    BitmapTexture mir_n(ramp(), BitmapFilter::Nearest, BitmapWrap::Mirror, UvTransform{});
    EXPECT_EQ(lookup(mir_n, 1.1f, 0.25f).r, 3.f);   // second tile is mirrored
    EXPECT_EQ(lookup(mir_n, 2.1f, 0.25f).r, 0.f);   // third is not
    EXPECT_EQ(lookup(mir_n, -0.1f, 0.25f).r, 0.f);  // mirrored about 0
}

TEST(Bitmap, MeanAndScalarLookupUseLuminance) {
    Image img(2, 2, Color3(1.f, 0.f, 0.f));
    BitmapTexture t(img, BitmapFilter::Nearest, BitmapWrap::Repeat, UvTransform{});
    EXPECT_NEAR(t.mean().r, 0.212671f, 1e-6f);
    SurfaceInteraction si;
    si.uv = Vec2f(0.3f, 0.3f);
    EXPECT_NEAR(t.eval_1(si), 0.212671f, 1e-6f);
}
