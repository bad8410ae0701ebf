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

}  // namespace
}  // namespace volguide
