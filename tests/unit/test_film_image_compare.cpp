// Image error metrics used by `volguide diff` and the equal-time benchmarks.
#include <gtest/gtest.h>

#include <cmath>

#include "volguide/render/image_compare.h"

namespace volguide {
namespace {

TEST(ImageCompare, RelMseMseMeansAndRatio) {
    Image ref(2, 1), img(2, 1);
    ref.at(0, 0) = Color3(1.f, 2.f, 0.f);
    ref.at(1, 0) = Color3(0.5f, 0.5f, 0.5f);
    img.at(0, 0) = Color3(1.5f, 2.f, 0.25f);
    img.at(1, 0) = Color3(0.5f, 0.f, 1.f);
    // Per channel: (I - R)^2 = 0.25, 0, 0.0625, 0, 0.25, 0.25 over R^2 = 1, 4, 0, 0.25, 0.25, 0.25.
    const double e2[6] = {0.25, 0, 0.0625, 0, 0.25, 0.25}, r2[6] = {1, 4, 0, 0.25, 0.25, 0.25};
    double rel2 = 0, rel3 = 0, mse = 0;
    for (int k = 0; k < 6; ++k) {
        rel2 += e2[k] / (r2[k] + 1e-2) / 6;
        rel3 += e2[k] / (r2[k] + 1e-3) / 6;
        mse += e2[k] / 6;
    }
    ImageDiff d = compare_images(img, ref);
    EXPECT_NEAR(d.relmse_1e2, rel2, 1e-12);
    EXPECT_NEAR(d.relmse_1e3, rel3, 1e-12);
    EXPECT_NEAR(d.mse, mse, 1e-12);
    EXPECT_NEAR(d.mean, 5.25 / 6, 1e-12);
    EXPECT_NEAR(d.reference_mean, 4.5 / 6, 1e-12);
    EXPECT_NEAR(d.ratio, 5.25 / 4.5, 1e-12);
    EXPECT_EQ(d.nonfinite, 0u);

    Image err = relative_error_image(img, ref, 1e-2);
    EXPECT_NEAR(err.at(0, 0).b, 0.0625 / 1e-2, 1e-4);
    EXPECT_NEAR(err.at(1, 0).g, 0.25 / 0.26, 1e-6);

    EXPECT_EQ(compare_images(ref, ref).relmse_1e3, 0.0);
    EXPECT_THROW(compare_images(Image(2, 2), ref), std::invalid_argument);
}

TEST(ImageCompare, NonFiniteValuesAreCountedNotSummed) {
    Image ref(1, 1, Color3(1.f)), img(1, 1, Color3(1.f));
    img.at(0, 0).g = std::nanf("");
    ImageDiff d = compare_images(img, ref);
    EXPECT_EQ(d.nonfinite, 1u);
    EXPECT_EQ(d.mse, 0.0);
    EXPECT_DOUBLE_EQ(d.ratio, 1.0);
}

TEST(ImageCompare, TrimmedRelMseDropsTheTopOneIn10000Pixels) {
    Image ref(100, 100, Color3(1.f)), img(100, 100, Color3(1.f));
    img.at(3, 5) = Color3(3.f);    // (3 - 1)^2 = 4 per channel: the one outlier of 10 000 pixels
    img.at(7, 7) = Color3(1.5f);   // 0.25 per channel
    const double n = 3.0 * 10000;  // pixel channels
    ImageDiff d = compare_images(img, ref);
    EXPECT_NEAR(d.relmse_1e2, 3 * (4 + 0.25) / 1.01 / n, 1e-12);
    EXPECT_NEAR(d.relmse_1e3, 3 * (4 + 0.25) / 1.001 / n, 1e-12);
    EXPECT_NEAR(d.relmse_1e2_trimmed, 3 * 0.25 / 1.01 / (n - 3), 1e-12);
    EXPECT_NEAR(d.relmse_1e3_trimmed, 3 * 0.25 / 1.001 / (n - 3), 1e-12);

    // Below 10 000 pixels nothing is trimmed.
    Image small_ref(99, 100, Color3(1.f)), small(99, 100, Color3(1.f));
    small.at(3, 5) = Color3(3.f);
    ImageDiff s = compare_images(small, small_ref);
    EXPECT_DOUBLE_EQ(s.relmse_1e3_trimmed, s.relmse_1e3);
    EXPECT_GT(s.relmse_1e3, 0);
}

TEST(ImageCompare, MinReferenceLeavesDarkReferencePixelsOut) {
    Image ref(3, 1), img(3, 1);
    ref.at(0, 0) = Color3(0.f);  // e.g. a pixel that sees no medium
    img.at(0, 0) = Color3(5.f);
    ref.at(1, 0) = Color3(1.f);
    img.at(1, 0) = Color3(1.5f);
    ref.at(2, 0) = Color3(2.f);
    img.at(2, 0) = Color3(2.f);
    ImageDiff all = compare_images(img, ref);
    EXPECT_EQ(all.pixels, 3u);
    ImageDiff lit = compare_images(img, ref, 0.0);
    EXPECT_EQ(lit.pixels, 2u);
    EXPECT_NEAR(lit.mse, 3 * 0.25 / 6, 1e-12);
    EXPECT_NEAR(lit.relmse_1e2, 3 * 0.25 / 1.01 / 6, 1e-12);
    EXPECT_NEAR(lit.reference_mean, 1.5, 1e-12);
    EXPECT_NEAR(lit.mean, 1.75, 1e-12);
    EXPECT_GT(all.mse, lit.mse);
}

TEST(ImageCompare, HeatmapIsMonotoneInTheErrorAndMarksNonFinite) {
    Image ref(4, 1, Color3(1.f)), img(4, 1, Color3(1.f));
    img.at(1, 0) = Color3(1.01f);  // relMSE ~ 1e-4: the bottom of the scale
    img.at(2, 0) = Color3(1.3f);   // ~ 0.09
    img.at(3, 0).r = std::nanf("");
    Image heat = relative_error_heatmap(img, ref);
    auto luminance = [](Color3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
    EXPECT_LT(luminance(heat.at(0, 0)), 1e-3);  // zero error: black
    EXPECT_LT(luminance(heat.at(0, 0)), luminance(heat.at(1, 0)) + 1e-6);
    EXPECT_LT(luminance(heat.at(1, 0)), luminance(heat.at(2, 0)));
    EXPECT_EQ(heat.at(3, 0).r, 1.f);
    EXPECT_EQ(heat.at(3, 0).g, 0.f);
    EXPECT_EQ(heat.at(3, 0).b, 1.f);
}

TEST(ImageCompare, MeanOfRendersEstimatesItsOwnError) {
    // One pixel; channels: renders {1, 3} -> mean 2, MSE (1 - 3)^2 / 4 = 1; {0.5, 0.5} -> 0; {2, 0} -> 1, 1.
    Image a(1, 1), b(1, 1);
    a.at(0, 0) = Color3(1.f, 0.5f, 2.f);
    b.at(0, 0) = Color3(3.f, 0.5f, 0.f);
    MeanEstimate m = mean_of_renders({a, b});
    EXPECT_FLOAT_EQ(m.mean.at(0, 0).r, 2.f);
    EXPECT_FLOAT_EQ(m.mean.at(0, 0).g, 0.5f);
    EXPECT_FLOAT_EQ(m.mean.at(0, 0).b, 1.f);
    EXPECT_NEAR(m.mse, (1 + 0 + 1) / 3.0, 1e-12);
    EXPECT_NEAR(m.relmse_1e2, (1 / 4.01 + 0 + 1 / 1.01) / 3, 1e-12);
    EXPECT_NEAR(m.relmse_1e3, (1 / 4.001 + 0 + 1 / 1.001) / 3, 1e-12);

    // Three renders 0, 1, 2: sample variance 1, MSE of the mean 1/3.
    Image c(1, 1, Color3(0.f)), d(1, 1, Color3(1.f)), e(1, 1, Color3(2.f));
    EXPECT_NEAR(mean_of_renders({c, d, e}).mse, 1.0 / 3, 1e-12);
    EXPECT_THROW(mean_of_renders({c}), std::invalid_argument);
    EXPECT_THROW(mean_of_renders({c, Image(2, 1)}), std::invalid_argument);
}

TEST(ImageCompare, MeanWithEarlierIsTheMeanOfAllRendersWithTheNewOnesSpread) {
    // Five renders 0, 1, 2 | 4, 8 (one pixel): the first three kept only as their mean 1. The
    // combined mean is that of all five (3); the error is the new pair's sample variance
    // ((4 - 8)^2 / 2 = 8) over the five renders.
    Image earlier(1, 1, Color3(1.f)), d(1, 1, Color3(4.f)), e(1, 1, Color3(8.f));
    MeanEstimate m = mean_with_earlier(earlier, 3, {d, e});
    EXPECT_FLOAT_EQ(m.mean.at(0, 0).r, 3.f);
    EXPECT_FLOAT_EQ(m.mean.at(0, 0).b, 3.f);
    EXPECT_NEAR(m.mse, 8.0 / 5, 1e-12);
    EXPECT_NEAR(m.relmse_1e2, 8.0 / 5 / (9 + 1e-2), 1e-12);

    // Made longer in two steps, the mean equals the one-step mean of the same renders (exact here:
    // every value is representable), and the error estimate is that of the same spread over more renders.
    Image a(1, 1, Color3(0.5f)), b(1, 1, Color3(1.5f));
    const MeanEstimate first = mean_of_renders({a, b});
    const MeanEstimate all = mean_of_renders({a, b, d, e});
    const MeanEstimate longer = mean_with_earlier(first.mean, 2, {d, e});
    EXPECT_FLOAT_EQ(longer.mean.at(0, 0).g, all.mean.at(0, 0).g);
    EXPECT_NEAR(longer.mse, 8.0 / 4, 1e-12);

    EXPECT_THROW(mean_with_earlier(earlier, 3, {d}), std::invalid_argument);
    EXPECT_THROW(mean_with_earlier(earlier, 0, {d, e}), std::invalid_argument);
    EXPECT_THROW(mean_with_earlier(Image(2, 1), 3, {d, e}), std::invalid_argument);
}

}  // namespace
}  // namespace volguide
