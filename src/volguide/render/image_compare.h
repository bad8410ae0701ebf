#pragma once
// Error metrics between an image and a reference (the `volguide diff` command and the equal-time
// benchmarks): relMSE(eps) = mean over pixels and channels of (I - R)^2 / (R^2 + eps).
#include "volguide/core/image.h"

namespace volguide {

struct ImageDiff {
    double relmse_1e2 = 0;  // eps = 1e-2
    double relmse_1e3 = 0;  // eps = 1e-3
    double mse = 0;
    double mean = 0;            // mean over pixels and channels of the image
    double reference_mean = 0;  // ... of the reference
    double ratio = 0;           // mean / reference_mean (NaN when the reference mean is 0)
    size_t nonfinite = 0;       // pixel channels of the image that are NaN/Inf (excluded from the sums)
};

// Throws std::invalid_argument when the sizes differ.
ImageDiff compare_images(const Image& image, const Image& reference);
// Per pixel and channel (I - R)^2 / (R^2 + eps).
Image relative_error_image(const Image& image, const Image& reference, double eps = 1e-2);

}  // namespace volguide
