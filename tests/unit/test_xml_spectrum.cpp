// Spectrum → linear sRGB as Mitsuba 3's RGB variants, and the CIE tables behind it.
#include <gtest/gtest.h>

#include <vector>

#include "test_loader_util.h"
#include "volguide/core/log.h"
#include "volguide/scene/cie1931.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// Mitsuba's Riemann sum over [360, 830] with 1000 points, for a flat unit spectrum.
Xyz integrate_flat(bool with_d65) {
    Xyz acc;
    for (int i = 0; i < 1000; ++i) {
        double w = kCieMin + i / 999.0 * (kCieMax - kCieMin);
        Xyz c = cie1931_xyz(w);
        double s = with_d65 ? cie_d65(w) : 1.0;
        acc.x += c.x * s;
        acc.y += c.y * s;
        acc.z += c.z * s;
    }
    double dw = (kCieMax - kCieMin) / 1000.0;
    return {acc.x * dw, acc.y * dw, acc.z * dw};
}

const std::vector<double> kFlatWl = {360.0, 830.0};
const std::vector<double> kFlatOne = {1.0, 1.0};

}  // namespace

TEST(Cie1931, TableMatchesMitsubasNormalisation) {
    // Mitsuba's MI_CIE_Y_NORMALIZATION is 1 / (this integral of ȳ); a mistyped ȳ entry breaks it.
    EXPECT_NEAR(integrate_flat(false).y, 106.7502593994140625, 1e-3);
    // x̄, ȳ, z̄ have (nearly) equal areas by construction of CIE XYZ.
    Xyz e = integrate_flat(false);
    EXPECT_NEAR(e.x / e.y, 1.0, 2e-3);
    EXPECT_NEAR(e.z / e.y, 1.0, 2e-3);
    // D65 is normalised so that its luminance is 1 after the ȳ normalisation.
    EXPECT_NEAR(integrate_flat(true).y * kCieYNormalization, 1.0, 2e-3);
}

TEST(Cie1931, InterpolatesAndVanishesOutsideRange) {
    EXPECT_NEAR(cie1931_xyz(555.0).y, 1.0, 1e-12);
    EXPECT_NEAR(cie1931_xyz(557.5).y, 0.5 * (1.0 + 0.995), 1e-12);
    EXPECT_EQ(cie1931_xyz(359.0).x, 0.0);
    EXPECT_EQ(cie1931_xyz(831.0).y, 0.0);
    EXPECT_NEAR(cie_d65(560.0) / kCieD65Normalization, 100.0, 1e-9);
}

TEST(SpectrumToRgb, FlatReflectanceIsWhite) {
    // A unit reflectance integrates against CMF × D65 → the D65 white point → (1, 1, 1).
    Color3 c = spectrum_to_linear_srgb(kFlatWl, kFlatOne, {}).rgb;
    EXPECT_NEAR(c.r, 1.f, 5e-3);
    EXPECT_NEAR(c.g, 1.f, 5e-3);
    EXPECT_NEAR(c.b, 1.f, 5e-3);
}

TEST(SpectrumToRgb, FlatEmitterIsEqualEnergyWhite) {
    // An emitter spectrum skips D65: equal-energy white, slightly pink in sRGB, luminance 1,
    // not clipped to 1 (emission is unbounded).
    SpectrumToRgbResult r = spectrum_to_linear_srgb(kFlatWl, std::vector<double>{2.0, 2.0}, {true, false});
    EXPECT_FALSE(r.clamped);
    EXPECT_NEAR(r.rgb.luminance(), 2.f, 5e-3);
    Color3 expected = xyz_to_linear_srgb({2.0, 2.0, 2.0});
    EXPECT_NEAR(r.rgb.r, expected.r, 1e-2);
    EXPECT_NEAR(r.rgb.g, expected.g, 1e-2);
    EXPECT_NEAR(r.rgb.b, expected.b, 1e-2);
    EXPECT_GT(r.rgb.r, 2.f);
}

TEST(SpectrumToRgb, BoundedValuesAreClipped) {
    SpectrumToRgbResult r = spectrum_to_linear_srgb(kFlatWl, std::vector<double>{3.0, 3.0}, {});
    EXPECT_TRUE(r.clamped);
    EXPECT_EQ(r.rgb, Color3(1.f));
    // eta/k style parameters are unbounded but still integrated with D65.
    SpectrumToRgbResult u = spectrum_to_linear_srgb(kFlatWl, std::vector<double>{3.0, 3.0}, {false, true});
    EXPECT_FALSE(u.clamped);
    EXPECT_NEAR(u.rgb.g, 3.f, 2e-2);
}

TEST(SpectrumToRgb, NarrowRedSpectrumIsRed) {
    std::vector<double> wl = {600, 650, 700}, v = {0, 1, 0};
    Color3 c = spectrum_to_linear_srgb(wl, v, {true, false}).rgb;
    EXPECT_GT(c.r, 5 * c.g);
    EXPECT_EQ(c.b, 0.f);  // negative blue is clamped at 0
}

TEST(SpectrumToRgb, OutsideTheListedRangeTheSpectrumIsZero) {
    // Doubling the spectrum inside its range doubles the result; nothing leaks outside it.
    std::vector<double> wl = {500, 600};
    Color3 a = spectrum_to_linear_srgb(wl, std::vector<double>{0.2, 0.2}, {true, false}).rgb;
    Color3 b = spectrum_to_linear_srgb(wl, std::vector<double>{0.4, 0.4}, {true, false}).rgb;
    EXPECT_NEAR(b.g, 2 * a.g, 1e-6);
    Color3 full = spectrum_to_linear_srgb(kFlatWl, std::vector<double>{0.2, 0.2}, {true, false}).rgb;
    EXPECT_LT(a.luminance(), full.luminance());
}

TEST(LoaderSpectrum, ConstantAndPairsThroughTheLoader) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene(R"(<bsdf type="diffuse">
  <spectrum name="reflectance" value="1"/>
  <spectrum name="flat" value="360:1, 830:1"/>
  <spectrum name="eta" value="360:3 830:3"/>
</bsdf>
<emitter type="area">
  <spectrum name="radiance" value="360:1, 830:1"/>
</emitter>
)"));
    Properties root = load_fake(path);
    Properties bsdf = child(root, "bsdf")->props;
    EXPECT_EQ(bsdf.get_color("reflectance"), Color3(1.f));
    Color3 flat = bsdf.get_color("flat");
    EXPECT_NEAR(flat.r, 1.f, 5e-3);
    EXPECT_NEAR(flat.g, 1.f, 5e-3);
    EXPECT_NEAR(flat.b, 1.f, 5e-3);
    EXPECT_GT(bsdf.get_color("eta").g, 2.9f);  // unbounded name: not clipped at 1
    Color3 radiance = child(root, "emitter")->props.get_color("radiance");
    EXPECT_GT(radiance.r, 1.1f);  // within an emitter: no D65, no clipping
    EXPECT_NEAR(radiance.luminance(), 1.f, 5e-3);
}

TEST(LoaderSpectrum, SpdFile) {
    ScratchDir dir;
    dir.write("data/red.spd", "# wavelength value\n600 0\n650 1\n700 0\n");
    std::string path = dir.write("s.xml", scene(R"(<emitter type="point">
  <spectrum name="intensity" filename="data/red.spd"/>
</emitter>
)"));
    Color3 c = child(load_fake(path), "emitter")->props.get_color("intensity");
    Color3 expected = spectrum_to_linear_srgb(std::vector<double>{600, 650, 700},
                                              std::vector<double>{0, 1, 0}, {true, false})
                          .rgb;
    EXPECT_EQ(c, expected);
}

// The out-of-gamut warning goes through core/log's handler (not straight to stderr), at the
// <spectrum>'s line.
TEST(SpectrumToRgb, OutOfGamutWarningGoesThroughTheLogHandler) {
    ScratchDir dir;
    const std::string path = dir.write(
        "s.xml", scene("<bsdf type=\"diffuse\">\n<spectrum name=\"reflectance\" value=\"400:3, 700:3\"/>\n</bsdf>\n"));
    std::vector<std::pair<int, std::string>> warnings;
    const WarningHandler previous = set_warning_handler(
        [&](const SourceLocation& loc, const std::string& m) { warnings.emplace_back(loc.line, m); });
    load_fake(path);
    set_warning_handler(previous);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0].first, 3);
    EXPECT_NE(warnings[0].second.find("out of the sRGB gamut"), std::string::npos) << warnings[0].second;
    EXPECT_NE(warnings[0].second.find("reflectance"), std::string::npos) << warnings[0].second;
}
