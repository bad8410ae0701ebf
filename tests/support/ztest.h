#pragma once
// Per-pixel z-test of a rendered mean against a reference mean and per-sample variance, as
// Mitsuba 3's own render tests do it (docs oracles.md §7).
#include <string>

#include "volguide/core/image.h"

namespace volguide::test {

struct ZTestResult {
    double pass_fraction = 0.0;  // of pixel-channels
    long failed = 0, total = 0;
    double significance = 0.0;   // Šidák-corrected per-pixel level
    bool passed = false;
    std::string summary() const;
};

// z = |mean - ref| * sqrt(spp / var_ref), var_ref clamped >= min_variance; p = 2(1 - Phi(z)); a
// pixel-channel passes when p >= 1 - (1 - alpha)^(1/#pixels); the image passes when at least
// `required_fraction` of pixel-channels pass. `error_mask` (optional) gets 1 where a channel failed.
//
// Like Mitsuba's test_renders.py, all three images are first converted from linear sRGB to XYZ
// (the variance image too, with the same linear map): Mitsuba's reference variances were computed
// in XYZ and stored as RGB, so their RGB channels can be negative and only make sense back in XYZ.
struct ZTestOptions {
    double alpha = 0.01;
    double required_fraction = 0.9975;
    double min_variance = 1e-4;
    bool in_xyz = true;
};
ZTestResult pixel_ztest(const Image& mean, double spp, const Image& ref, const Image& ref_var,
                        const ZTestOptions& options = {}, Image* error_mask = nullptr);

// The per-sample variance averaged over the (2r+1)^2 window around each pixel (clamped at the
// borders). A pixel's own sample variance is unreliable where the weights are heavy-tailed: a pixel
// that missed its rare large samples reads both a low mean and a low variance, so its z-score is
// inflated; its neighbours' variance is the same up to the scene's smooth variation.
Image smoothed_variance(const Image& var, int r);

// The z-test of an estimator whose variance is not the reference's (guided_volpath against Mitsuba's
// volpath/path references): `mean` against `ref` with the estimator's own per-sample variance
// `own_var` averaged over 3x3 pixels (smoothed_variance: the pixel's own value is too small where it
// missed its rare large samples; the media suite's rule, unchanged since issue 7). In RGB (a
// variance image cannot be mapped to XYZ without the channels' covariance). `rejects_dark` gets whether
// the same test rejects `mean` scaled by 0.75 (its power: a test that cannot fail proves nothing).
ZTestResult own_variance_ztest(const Image& mean, double spp, const Image& ref, const Image& own_var,
                               bool* rejects_dark, Image* error_mask = nullptr);

// Mitsuba's linear sRGB → CIE XYZ matrix, applied to every pixel.
Image srgb_to_xyz(const Image& rgb);

// Mean and standard error of the mean of an image rendered with `spp` samples per pixel, given its
// per-sample variance image: Var(mean) = sum(var) / (spp * n^2) over n pixel-channels.
struct ImageMean {
    double mean = 0.0, stderr_ = 0.0;
};
ImageMean image_mean(const Image& mean, const Image& var, double spp);

}  // namespace volguide::test
