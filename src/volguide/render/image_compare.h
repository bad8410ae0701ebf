#pragma once
// Error metrics between an image and a reference (the `volguide diff` command and the equal-time
// benchmarks): relMSE(eps) = mean over pixels and channels of (I - R)^2 / (R^2 + eps).
#include <limits>
#include <vector>

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
    // The same relMSEs after discarding the pixels with the top 0.01 % errors (per-pixel error = mean
    // of its channels), as Herholz's evaluation scripts do (docs/theory.md §12.1); equal to the untrimmed
    // values below 10 000 pixels, where 0.01 % is less than one pixel.
    double relmse_1e2_trimmed = 0, relmse_1e3_trimmed = 0;
    size_t pixels = 0;  // pixels compared (all, unless min_reference left some out)
};

// Fraction of pixels the trimmed relMSE discards.
inline constexpr double kOutlierFraction = 1e-4;

// Throws std::invalid_argument when the sizes differ. Pixels whose reference (mean of its channels)
// is not above `min_reference` are left out of every figure (e.g. the pixels that see no medium
// when judging a volume-only estimate); `pixels` counts those that were kept.
ImageDiff compare_images(const Image& image, const Image& reference,
                         double min_reference = -std::numeric_limits<double>::infinity());
// Per pixel and channel (I - R)^2 / (R^2 + eps).
Image relative_error_image(const Image& image, const Image& reference, double eps = 1e-2);
// False-colour map of the per-pixel relMSE (mean of the channels, eps 1e-2) on a log scale: black-violet
// at <= 1e-4 through red and orange to pale yellow at >= 10; magenta marks non-finite pixels. Linear RGB
// (write it as PNG for viewing).
Image relative_error_heatmap(const Image& image, const Image& reference, double eps = 1e-2);

// The mean of k >= 2 independent renders of the same image and an unbiased estimate of that mean's
// own error: per pixel and channel, MSE = s^2 / k with s^2 the sample variance of the k renders
// (for k = 2, (A - B)^2 / 4), relMSE divides it by (mean^2 + eps). Used to certify references.
struct MeanEstimate {
    Image mean;
    double relmse_1e2 = 0, relmse_1e3 = 0, mse = 0;
};
// Throws std::invalid_argument for fewer than 2 images or different sizes.
MeanEstimate mean_of_renders(const std::vector<Image>& renders);

// A reference made longer: `earlier` is the mean of `earlier_count` renders made before (their images
// are not kept), `renders` are k >= 2 more of the same kind (same method and samples per render, other
// seeds). The mean is that of all earlier_count + k renders, (earlier_count * earlier + sum) /
// (earlier_count + k); its MSE is s^2 / (earlier_count + k) with s^2 the sample variance of the k new
// renders alone: an unbiased estimate of every render's variance (the earlier ones' spread is lost with
// their images) with k - 1 degrees of freedom per pixel, so noisier per pixel than an estimate from
// all renders; its mean over the image's many pixels is what certifies a reference.
// Throws std::invalid_argument for fewer than 2 new renders, earlier_count < 1 or different sizes.
MeanEstimate mean_with_earlier(const Image& earlier, int earlier_count, const std::vector<Image>& renders);

}  // namespace volguide
