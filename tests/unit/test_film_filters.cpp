// Reconstruction filters (values and integrals, Mitsuba's formulas) and the film's splatting and
// normalisation.
#include <gtest/gtest.h>

#include <cmath>

#include "volguide/core/properties.h"
#include "volguide/render/sensors/film_buffer.h"
#include "volguide/render/sensors/rfilters.h"
#include "volguide/scene/factories.h"

namespace volguide {
namespace {

const SourceLocation kFilterLoc{"filter_test.xml", 3};

double integrate_filter(const ReconstructionFilter& f) {
    // Midpoint rule over [-r, r]; the filters are continuous except the box's end points.
    const int n = 200000;
    double r = f.radius() + 0.25, h = 2 * r / n, s = 0;
    for (int i = 0; i < n; ++i) s += f.eval(float(-r + (i + 0.5) * h));
    return s * h;
}

TEST(Filters, Box) {
    BoxFilter f;
    EXPECT_EQ(f.radius(), 0.5f);
    EXPECT_EQ(f.eval(0.f), 1.f);
    EXPECT_EQ(f.eval(0.49f), 1.f);
    EXPECT_EQ(f.eval(-0.49f), 1.f);
    EXPECT_EQ(f.eval(0.51f), 0.f);
    EXPECT_NEAR(integrate_filter(f), 1.0, 1e-4);
    EXPECT_EQ(filter_border_size(f), 0);
}

TEST(Filters, TentDefaultAndRadius) {
    auto f =
        std::dynamic_pointer_cast<ReconstructionFilter>(create_rfilter(Properties("rfilter", "tent", kFilterLoc)));
    EXPECT_EQ(f->radius(), 1.f);
    EXPECT_FLOAT_EQ(f->eval(0.f), 1.f);
    EXPECT_FLOAT_EQ(f->eval(0.25f), 0.75f);
    EXPECT_FLOAT_EQ(f->eval(-0.5f), 0.5f);
    EXPECT_EQ(f->eval(1.f), 0.f);
    EXPECT_NEAR(integrate_filter(*f), 1.0, 1e-6);  // integral of a tent = its radius
    EXPECT_EQ(filter_border_size(*f), 1);

    Properties p("rfilter", "tent", kFilterLoc);
    p.set("radius", "float", 2.5, kFilterLoc);
    auto wide = std::dynamic_pointer_cast<ReconstructionFilter>(create_rfilter(p));
    p.check_all_used();
    EXPECT_FLOAT_EQ(wide->eval(1.25f), 0.5f);
    EXPECT_NEAR(integrate_filter(*wide), 2.5, 1e-5);
    EXPECT_EQ(filter_border_size(*wide), 2);

    Properties bad("rfilter", "tent", kFilterLoc);
    bad.set("radius", "float", -1.0, kFilterLoc);
    EXPECT_THROW(create_rfilter(bad), InputError);
}

TEST(Filters, GaussianMatchesMitsubasWindowedFormula) {
    GaussianFilter f;  // stddev 0.5
    EXPECT_FLOAT_EQ(f.radius(), 2.f);
    const double bias = std::exp(-8.0);  // exp(-radius^2 / (2 stddev^2)) with radius = 4 stddev
    EXPECT_NEAR(f.eval(0.f), 1.0 - bias, 1e-6);
    EXPECT_NEAR(f.eval(0.5f), std::exp(-0.5) - bias, 1e-6);
    EXPECT_NEAR(f.eval(-1.f), std::exp(-2.0) - bias, 1e-6);
    EXPECT_EQ(f.eval(2.f), 0.f);
    EXPECT_EQ(f.eval(3.f), 0.f);
    // Integral: sqrt(2 pi) stddev erf(4 / sqrt 2) - 2 radius bias.
    const double s = 0.5,
                 expected = std::sqrt(2 * M_PI) * s * std::erf(4 / std::sqrt(2.0)) - 2 * 4 * s * bias;
    EXPECT_NEAR(integrate_filter(f), expected, 1e-5);
    EXPECT_EQ(filter_border_size(f), 2);

    Properties p("rfilter", "gaussian", kFilterLoc);
    p.set("stddev", "float", 0.25, kFilterLoc);
    auto narrow = std::dynamic_pointer_cast<GaussianFilter>(create_rfilter(p));
    EXPECT_FLOAT_EQ(narrow->radius(), 1.f);
    EXPECT_NEAR(narrow->eval(0.25f), std::exp(-0.5) - bias, 1e-6);
    EXPECT_THROW(create_rfilter(Properties("rfilter", "sinc", kFilterLoc)), InputError);
}

TEST(Filters, MitchellCatmullRomAndLanczos) {
    auto mitchell = std::dynamic_pointer_cast<ReconstructionFilter>(
        create_rfilter(Properties("rfilter", "mitchell", kFilterLoc)));
    EXPECT_EQ(mitchell->radius(), 2.f);
    // B = C = 1/3: k(0) = (6 - 2B) / 6 = 8/9, k(1) = B / 6 = 1/18, zero from 2 on.
    EXPECT_NEAR(mitchell->eval(0.f), 8.f / 9.f, 1e-6f);
    EXPECT_NEAR(mitchell->eval(1.f), 1.f / 18.f, 1e-6f);
    EXPECT_NEAR(mitchell->eval(-1.f), 1.f / 18.f, 1e-6f);
    EXPECT_EQ(mitchell->eval(2.f), 0.f);
    EXPECT_NEAR(integrate_filter(*mitchell), 1.0, 1e-5);  // BC-splines integrate to one

    Properties p("rfilter", "mitchell", kFilterLoc);
    p.set("B", "float", 0.25, kFilterLoc);
    p.set("C", "float", 0.55, kFilterLoc);
    auto custom = std::dynamic_pointer_cast<ReconstructionFilter>(create_rfilter(p));
    p.check_all_used();
    EXPECT_NEAR(custom->eval(0.f), (6 - 2 * 0.25) / 6, 1e-6);
    EXPECT_NEAR(integrate_filter(*custom), 1.0, 1e-5);

    auto cr = std::dynamic_pointer_cast<ReconstructionFilter>(
        create_rfilter(Properties("rfilter", "catmullrom", kFilterLoc)));
    // Interpolating: 1 at 0, 0 at the other integers; negative lobe in between.
    EXPECT_NEAR(cr->eval(0.f), 1.f, 1e-6f);
    EXPECT_NEAR(cr->eval(1.f), 0.f, 1e-6f);
    EXPECT_LT(cr->eval(1.5f), 0.f);
    EXPECT_NEAR(integrate_filter(*cr), 1.0, 1e-5);

    auto lanczos = std::dynamic_pointer_cast<ReconstructionFilter>(
        create_rfilter(Properties("rfilter", "lanczos", kFilterLoc)));
    EXPECT_EQ(lanczos->radius(), 3.f);
    EXPECT_EQ(lanczos->eval(0.f), 1.f);
    for (float k : {1.f, 2.f, 3.f}) EXPECT_NEAR(lanczos->eval(k), 0.f, 1e-6f);
    // sinc(x) sinc(x/3) at x = 0.5.
    const double a = M_PI * 0.5;
    EXPECT_NEAR(lanczos->eval(0.5f), std::sin(a) * std::sin(a / 3) / (a * a / 3), 1e-6);
    EXPECT_EQ(lanczos->eval(3.5f), 0.f);
    Properties bad("rfilter", "lanczos", kFilterLoc);
    bad.set("lobes", "integer", int64_t(0), kFilterLoc);
    EXPECT_THROW(create_rfilter(bad), InputError);
}

TEST(FilmBuffer, BoxFilterAveragesTheSamplesOfEachPixel) {
    BoxFilter box;
    Splatter splatter(box, 4, 3);
    PixelRect all{0, 0, 4, 3};
    TileBuffer tile(splatter, splatter.footprint(all), true);
    tile.splat({1.2f, 2.7f}, Color3(1.f, 2.f, 3.f));
    tile.splat({1.9f, 2.1f}, Color3(3.f, 2.f, 1.f));
    tile.splat({0.f, 0.f}, Color3(5.f));
    FilmBuffer film(4, 3, true);
    film.add(tile);
    Image mean = film.mean(), var = film.variance();
    EXPECT_EQ(mean.at(1, 2), Color3(2.f, 2.f, 2.f));
    EXPECT_EQ(var.at(1, 2), Color3(1.f, 0.f, 1.f));
    EXPECT_EQ(mean.at(0, 0), Color3(5.f));
    EXPECT_EQ(var.at(0, 0), Color3(0.f));
    EXPECT_EQ(mean.at(2, 1), Color3(0.f));  // no sample: black, not NaN
}

TEST(FilmBuffer, SplatsWithNormalisedFilterWeights) {
    TentFilter tent(1.f);
    Splatter splatter(tent, 5, 5);
    PixelRect centre{2, 2, 3, 3};
    TileBuffer tile(splatter, splatter.footprint(centre), false);
    EXPECT_EQ(tile.rect().x0, 0);
    EXPECT_EQ(tile.rect().x1, 5);
    // A sample at (2.75, 2.5): horizontal distances to centres 2.5 and 3.5 are 0.25 and 0.75.
    tile.splat({2.75f, 2.5f}, Color3(4.f));
    tile.splat({2.25f, 2.5f}, Color3(8.f));
    FilmBuffer film(5, 5, false);
    film.add(tile);
    Image m = film.mean();
    // Pixel 2 sees both samples with weight 0.75 each; pixel 3 only the first (0.25); pixel 1 only the
    // second.
    EXPECT_FLOAT_EQ(m.at(2, 2).r, 6.f);
    EXPECT_FLOAT_EQ(m.at(3, 2).r, 4.f);
    EXPECT_FLOAT_EQ(m.at(1, 2).r, 8.f);
    EXPECT_EQ(m.at(2, 1).r, 0.f);  // vertical distance 1: weight 0
    EXPECT_TRUE(film.variance().pixels.empty());
}

TEST(FilmBuffer, ConstantSignalStaysConstantWithAGaussian) {
    GaussianFilter g;
    Splatter splatter(g, 6, 4);
    PixelRect all{0, 0, 6, 4};
    TileBuffer tile(splatter, splatter.footprint(all), true);
    for (int k = 0; k < 500; ++k) {
        float x = 6.f * float((k * 37) % 500) / 500.f, y = 4.f * float((k * 91) % 500) / 500.f;
        tile.splat({x, y}, Color3(0.3f, 0.6f, 0.9f));
    }
    FilmBuffer film(6, 4, true);
    film.add(tile);
    Image m = film.mean(), v = film.variance();
    for (const Color3& c : m.pixels) {
        EXPECT_NEAR(c.r, 0.3f, 1e-6f);
        EXPECT_NEAR(c.b, 0.9f, 1e-6f);
    }
    for (const Color3& c : v.pixels) EXPECT_NEAR(c.g, 0.f, 1e-6f);
}

}  // namespace
}  // namespace volguide
