#include "support/ztest.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace volguide::test {

std::string ZTestResult::summary() const {
    return fmt::format("{} of {} pixel-channels failed (pass fraction {:.5f}, per-pixel level {:.3g}) → {}", failed,
                       total, pass_fraction, significance, passed ? "PASS" : "FAIL");
}

Image srgb_to_xyz(const Image& rgb) {
    Image out = rgb;
    for (auto& p : out.pixels) {
        const Color3 c = p;
        p = Color3(0.412453f * c.r + 0.357580f * c.g + 0.180423f * c.b,
                   0.212671f * c.r + 0.715160f * c.g + 0.072169f * c.b,
                   0.019334f * c.r + 0.119193f * c.g + 0.950227f * c.b);
    }
    return out;
}

ZTestResult pixel_ztest(const Image& mean_in, double spp, const Image& ref_in, const Image& ref_var_in,
                        const ZTestOptions& options, Image* error_mask) {
    const double alpha = options.alpha, required_fraction = options.required_fraction,
                 min_variance = options.min_variance;
    const Image mean = options.in_xyz ? srgb_to_xyz(mean_in) : mean_in;
    const Image ref = options.in_xyz ? srgb_to_xyz(ref_in) : ref_in;
    const Image ref_var = options.in_xyz ? srgb_to_xyz(ref_var_in) : ref_var_in;
    if (mean.width != ref.width || mean.height != ref.height || ref_var.width != ref.width ||
        ref_var.height != ref.height)
        throw std::invalid_argument("pixel_ztest: image sizes differ");
    const long pixels = long(ref.width) * ref.height;
    ZTestResult r;
    r.significance = 1.0 - std::pow(1.0 - alpha, 1.0 / double(pixels));
    if (error_mask) *error_mask = Image(ref.width, ref.height);
    for (long i = 0; i < pixels; ++i)
        for (int c = 0; c < 3; ++c) {
            double var = std::max(double(ref_var.pixels[i][c]), min_variance);
            double z = std::abs(double(mean.pixels[i][c]) - ref.pixels[i][c]) * std::sqrt(spp / var);
            double p = std::erfc(z / std::sqrt(2.0));
            ++r.total;
            if (!(p >= r.significance)) {
                ++r.failed;
                if (error_mask) error_mask->pixels[i][c] = 1.f;
            }
        }
    r.pass_fraction = 1.0 - double(r.failed) / double(r.total);
    r.passed = r.pass_fraction >= required_fraction;
    return r;
}

Image smoothed_variance(const Image& var, int r) {
    Image out(var.width, var.height);
    for (int y = 0; y < var.height; ++y)
        for (int x = 0; x < var.width; ++x) {
            Color3 sum(0.f);
            int n = 0;
            for (int yy = std::max(0, y - r); yy <= std::min(var.height - 1, y + r); ++yy)
                for (int xx = std::max(0, x - r); xx <= std::min(var.width - 1, x + r); ++xx) {
                    sum += var.at(xx, yy);
                    ++n;
                }
            out.at(x, y) = sum * (1.f / float(n));
        }
    return out;
}

ZTestResult own_variance_ztest(const Image& mean, double spp, const Image& ref, const Image& own_var,
                               bool* rejects_dark, Image* error_mask) {
    ZTestOptions options;
    options.in_xyz = false;
    const Image variance = smoothed_variance(own_var, 1);
    Image dark = mean;
    for (Color3& p : dark.pixels) p = p * 0.75f;
    *rejects_dark = !pixel_ztest(dark, spp, ref, variance, options).passed;
    return pixel_ztest(mean, spp, ref, variance, options, error_mask);
}

ImageMean image_mean(const Image& mean, const Image& var, double spp) {
    double sum = 0.0, var_sum = 0.0;
    const double n = double(mean.pixels.size()) * 3.0;
    for (size_t i = 0; i < mean.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            sum += mean.pixels[i][c];
            var_sum += var.pixels[i][c];
        }
    return {sum / n, std::sqrt(var_sum / (spp * n * n))};
}

}  // namespace volguide::test
