#include "volguide/render/image_compare.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace volguide {

namespace {
void check_sizes(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        throw std::invalid_argument("image size " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                                    " differs from the reference's " + std::to_string(b.width) + "x" +
                                    std::to_string(b.height));
}
}  // namespace

ImageDiff compare_images(const Image& image, const Image& reference) {
    check_sizes(image, reference);
    ImageDiff d;
    double rel2 = 0, rel3 = 0, se = 0, sum_i = 0, sum_r = 0;
    size_t n = 0;
    for (size_t p = 0; p < image.pixels.size(); ++p)
        for (int c = 0; c < 3; ++c) {
            double i = image.pixels[p][c], r = reference.pixels[p][c];
            if (!std::isfinite(i) || !std::isfinite(r)) {
                ++d.nonfinite;
                continue;
            }
            double e2 = (i - r) * (i - r);
            rel2 += e2 / (r * r + 1e-2);
            rel3 += e2 / (r * r + 1e-3);
            se += e2;
            sum_i += i;
            sum_r += r;
            ++n;
        }
    if (n > 0) {
        d.relmse_1e2 = rel2 / double(n);
        d.relmse_1e3 = rel3 / double(n);
        d.mse = se / double(n);
        d.mean = sum_i / double(n);
        d.reference_mean = sum_r / double(n);
    }
    d.ratio = d.reference_mean != 0 ? d.mean / d.reference_mean : std::numeric_limits<double>::quiet_NaN();
    return d;
}

Image relative_error_image(const Image& image, const Image& reference, double eps) {
    check_sizes(image, reference);
    Image out(image.width, image.height);
    for (size_t p = 0; p < image.pixels.size(); ++p)
        for (int c = 0; c < 3; ++c) {
            double i = image.pixels[p][c], r = reference.pixels[p][c];
            out.pixels[p][c] = float((i - r) * (i - r) / (r * r + eps));
        }
    return out;
}

}  // namespace volguide
