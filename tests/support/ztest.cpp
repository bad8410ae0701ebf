#include "support/ztest.h"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace volguide::test {

std::string ZTestResult::summary() const {
    return fmt::format("{} of {} pixel-channels failed (pass fraction {:.5f}, per-pixel level {:.3g}) → {}", failed,
                       total, pass_fraction, significance, passed ? "PASS" : "FAIL");
}

ZTestResult pixel_ztest(const Image& mean, double spp, const Image& ref, const Image& ref_var, double alpha,
                        double required_fraction, double min_variance, Image* error_mask) {
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
