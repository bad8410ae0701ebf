// The PNG tonemap (render/tonemap.h): the default is the sRGB preview volguide always wrote; Mitsuba
// 0.6's ldrfilm adds an exposure and a gamma curve, or Reinhard et al.'s operator (issue 50).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "support/cli.h"
#include "support/test_support.h"
#include "volguide/render/image_io.h"
#include "volguide/render/sensor.h"
#include "volguide/render/sensors/hdrfilm.h"
#include "volguide/render/srgb.h"
#include "volguide/render/tonemap.h"

using namespace volguide;

namespace {

Image tonemap_row(std::initializer_list<Color3> pixels) {
    Image image(int(pixels.size()), 1);
    int i = 0;
    for (const Color3& c : pixels) image.at(i++, 0) = c;
    return image;
}

Properties ldrfilm_props() {
    Properties p("film", "ldrfilm", SourceLocation{"scene.xml", 4});
    p.set("width", "integer", int64_t(4), SourceLocation{"scene.xml", 5});
    p.set("height", "integer", int64_t(4), SourceLocation{"scene.xml", 6});
    return p;
}

}  // namespace

TEST(PngTonemap, DefaultIsTheSrgbPreview) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Image image = tonemap_row({Color3(0.f, 0.002f, 0.5f), Color3(-1.f, 1.f, 7.f), Color3(nan, 0.18f, 0.9f)});
    volguide::test::TempDir dir("tonemap");
    write_png(dir.file("a.png"), image);
    const Image png = read_image(dir.file("a.png"), /*raw=*/true);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            float v = image.pixels[i][c];
            v = std::isnan(v) ? 0.f : std::clamp(v, 0.f, 1.f);
            EXPECT_FLOAT_EQ(png.pixels[i][c], float(std::lround(linear_to_srgb(v) * 255.f)) / 255.f) << i << " " << c;
        }
}

TEST(PngTonemap, ExposureAndGamma) {
    const Image image = tonemap_row({Color3(0.1f, 0.2f, 0.7f)});
    PngTonemap t;
    t.exposure = 1;
    Image d = display_values(image, t);
    EXPECT_FLOAT_EQ(d.at(0, 0).r, linear_to_srgb(0.2f));
    EXPECT_FLOAT_EQ(d.at(0, 0).b, 1.f);  // 1.4 clamped
    t = PngTonemap{};
    t.gamma = 2.2f;
    d = display_values(image, t);
    EXPECT_FLOAT_EQ(d.at(0, 0).g, std::pow(0.2f, 1 / 2.2f));
}

TEST(PngTonemap, ReinhardMapsTheBrightestPixelToWhite) {
    // Grey 0.1 and grey 1, key 0.18, no burn: Lp = L key / exp(mean log(1e-3 + L)) and
    // L' = Lp (1 + Lp / Lw^2) / (1 + Lp) with Lw the brightest Lp, so the brightest pixel becomes 1.
    const Image image = tonemap_row({Color3(0.1f), Color3(1.f), Color3(0.3f, 0.1f, 0.05f)});
    PngTonemap t;
    t.method = PngTonemap::Method::reinhard;
    t.gamma = 1;
    const Image d = display_values(image, t);
    EXPECT_NEAR(d.at(1, 0).g, 1.f, 1e-6f);
    const double lum3 = 0.3 * 0.212671 + 0.1 * 0.715160 + 0.05 * 0.072169;
    const double log_average = std::exp((std::log(1e-3 + 0.1) + std::log(1e-3 + 1.0) + std::log(1e-3 + lum3)) / 3);
    const double scale = 0.18 / log_average, white = scale;
    const double lp = 0.1 * scale, expected = lp * (1 + lp / (white * white)) / (1 + lp);
    EXPECT_NEAR(d.at(0, 0).r, expected, 1e-5);
    // Chromaticity is kept: the channels of a coloured pixel keep their ratios.
    EXPECT_NEAR(d.at(2, 0).r / d.at(2, 0).g, 3.0, 1e-4);
    // burn lowers the white point: the brightest pixel burns out (clamped at 1), others get brighter.
    t.burn = 0.5f;
    const Image burnt = display_values(image, t);
    EXPECT_GT(burnt.at(0, 0).r, d.at(0, 0).r);
    // A black image stays black.
    EXPECT_EQ(display_values(tonemap_row({Color3(0.f)}), t).at(0, 0).r, 0.f);
}

TEST(PngTonemap, LdrfilmReadsItsTonemap) {
    Properties p = ldrfilm_props();
    p.set("tonemap_method", "string", std::string("reinhard"), SourceLocation{"scene.xml", 7});
    p.set("key", "float", 0.3, SourceLocation{"scene.xml", 8});
    auto film = make_ldrfilm(p);
    EXPECT_EQ(film->png_tonemap().method, PngTonemap::Method::reinhard);
    EXPECT_FLOAT_EQ(film->png_tonemap().key, 0.3f);
    EXPECT_EQ(film->width(), 4);
    // What a method does not use is an error at its line, as is an unknown method.
    Properties q = ldrfilm_props();
    q.set("burn", "float", 0.3, SourceLocation{"scene.xml", 9});
    try {
        make_ldrfilm(q);
        ADD_FAILURE() << "burn with the gamma method accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.location().line, 9);
    }
    Properties r = ldrfilm_props();
    r.set("tonemap_method", "string", std::string("filmic"), SourceLocation{"scene.xml", 10});
    EXPECT_THROW(make_ldrfilm(r), InputError);
    // An hdrfilm writes the default preview.
    Properties h("film", "hdrfilm", SourceLocation{"scene.xml", 4});
    EXPECT_EQ(make_hdrfilm(h)->png_tonemap().gamma, -1.f);
}
