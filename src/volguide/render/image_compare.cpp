#include "volguide/render/image_compare.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "volguide/render/srgb.h"

namespace volguide {

namespace {
void check_sizes(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        throw std::invalid_argument("image size " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                                    " differs from the reference's " + std::to_string(b.width) + "x" +
                                    std::to_string(b.height));
}
}  // namespace

ImageDiff compare_images(const Image& image, const Image& reference, double min_reference) {
    check_sizes(image, reference);
    ImageDiff d;
    double rel2 = 0, rel3 = 0, se = 0, sum_i = 0, sum_r = 0;
    size_t n = 0;
    // Per pixel: (sum of rel errors, eps 1e-2 and 1e-3, and its finite channel count) for trimming.
    struct PixelError {
        double rel2 = 0, rel3 = 0;
        int channels = 0;
    };
    std::vector<PixelError> pixel_errors(image.pixels.size());
    for (size_t p = 0; p < image.pixels.size(); ++p) {
        const Color3& ref = reference.pixels[p];
        const double ref_mean = (double(ref.r) + ref.g + ref.b) / 3.0;
        if (std::isfinite(ref_mean) && !(ref_mean > min_reference)) continue;  // non-finite: counted below
        ++d.pixels;
        for (int c = 0; c < 3; ++c) {
            double i = image.pixels[p][c], r = reference.pixels[p][c];
            if (!std::isfinite(i) || !std::isfinite(r)) {
                ++d.nonfinite;
                continue;
            }
            double e2 = (i - r) * (i - r);
            rel2 += e2 / (r * r + 1e-2);
            rel3 += e2 / (r * r + 1e-3);
            pixel_errors[p].rel2 += e2 / (r * r + 1e-2);
            pixel_errors[p].rel3 += e2 / (r * r + 1e-3);
            pixel_errors[p].channels += 1;
            se += e2;
            sum_i += i;
            sum_r += r;
            ++n;
        }
    }
    if (n > 0) {
        d.relmse_1e2 = rel2 / double(n);
        d.relmse_1e3 = rel3 / double(n);
        d.mse = se / double(n);
        d.mean = sum_i / double(n);
        d.reference_mean = sum_r / double(n);
    }
    d.ratio = d.reference_mean != 0 ? d.mean / d.reference_mean : std::numeric_limits<double>::quiet_NaN();

    // Trimmed: drop the floor(N * 1e-4) pixels of largest mean channel error (ranked with eps 1e-3;
    // ties broken by index, so the result does not depend on the sort).
    std::vector<size_t> order;
    for (size_t p = 0; p < pixel_errors.size(); ++p)
        if (pixel_errors[p].channels > 0) order.push_back(p);
    const size_t drop = size_t(std::floor(double(order.size()) * kOutlierFraction));
    auto worse = [&](size_t a, size_t b) {
        double ea = pixel_errors[a].rel3 / pixel_errors[a].channels;
        double eb = pixel_errors[b].rel3 / pixel_errors[b].channels;
        return ea != eb ? ea > eb : a < b;
    };
    if (drop > 0) std::partial_sort(order.begin(), order.begin() + drop, order.end(), worse);
    double t2 = 0, t3 = 0;
    size_t tn = 0;
    for (size_t k = drop; k < order.size(); ++k) {
        const PixelError& e = pixel_errors[order[k]];
        t2 += e.rel2;
        t3 += e.rel3;
        tn += e.channels;
    }
    if (tn > 0) {
        d.relmse_1e2_trimmed = t2 / double(tn);
        d.relmse_1e3_trimmed = t3 / double(tn);
    }
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

namespace {
// Approximately matplotlib's "inferno" (sRGB), at t = 0, 0.25, 0.5, 0.75, 1.
constexpr std::array<std::array<float, 3>, 5> kHeat = {{{0.00f, 0.00f, 0.02f},
                                                         {0.34f, 0.06f, 0.43f},
                                                         {0.73f, 0.21f, 0.33f},
                                                         {0.98f, 0.55f, 0.04f},
                                                         {0.99f, 1.00f, 0.64f}}};

Color3 heat_color(double t) {
    t = std::clamp(t, 0.0, 1.0) * double(kHeat.size() - 1);
    size_t k = std::min(size_t(t), kHeat.size() - 2);
    float f = float(t - double(k));
    Color3 c;
    for (int i = 0; i < 3; ++i) c[i] = srgb_to_linear(kHeat[k][i] * (1 - f) + kHeat[k + 1][i] * f);
    return c;
}
}  // namespace

Image relative_error_heatmap(const Image& image, const Image& reference, double eps) {
    check_sizes(image, reference);
    Image out(image.width, image.height);
    for (size_t p = 0; p < image.pixels.size(); ++p) {
        double sum = 0;
        bool finite = true;
        for (int c = 0; c < 3; ++c) {
            double i = image.pixels[p][c], r = reference.pixels[p][c];
            finite = finite && std::isfinite(i) && std::isfinite(r);
            sum += (i - r) * (i - r) / (r * r + eps);
        }
        if (!finite) {
            out.pixels[p] = Color3(1.f, 0.f, 1.f);
            continue;
        }
        double v = sum / 3;  // 1e-4 -> 0, 10 -> 1
        out.pixels[p] = heat_color(v > 0 ? (std::log10(v) + 4.0) / 5.0 : 0.0);
    }
    return out;
}

namespace {

// Mean and error of `earlier_count` earlier renders (mean `earlier`, may be null with count 0) and the
// k new ones; the spread is measured on the new renders only.
MeanEstimate combined_mean(const Image* earlier, int earlier_count, const std::vector<Image>& renders) {
    if (renders.size() < 2) throw std::invalid_argument("the error of a mean needs at least 2 renders");
    for (const Image& r : renders) check_sizes(r, renders.front());
    if (earlier) check_sizes(*earlier, renders.front());
    const double k = double(renders.size()), total = k + earlier_count;
    MeanEstimate m;
    m.mean = Image(renders.front().width, renders.front().height);
    double rel2 = 0, rel3 = 0, se = 0;
    for (size_t p = 0; p < m.mean.pixels.size(); ++p)
        for (int c = 0; c < 3; ++c) {
            double sum = 0;
            for (const Image& r : renders) sum += r.pixels[p][c];
            const double new_mean = sum / k;
            double ss = 0;
            for (const Image& r : renders) ss += (r.pixels[p][c] - new_mean) * (r.pixels[p][c] - new_mean);
            const double mean =
                earlier ? (sum + double(earlier_count) * earlier->pixels[p][c]) / total : new_mean;
            const double mse = ss / (k - 1) / total;  // sample variance / number of renders
            m.mean.pixels[p][c] = float(mean);
            se += mse;
            rel2 += mse / (mean * mean + 1e-2);
            rel3 += mse / (mean * mean + 1e-3);
        }
    const double n = double(m.mean.pixels.size()) * 3;
    if (n > 0) {
        m.relmse_1e2 = rel2 / n;
        m.relmse_1e3 = rel3 / n;
        m.mse = se / n;
    }
    return m;
}

}  // namespace

MeanEstimate mean_of_renders(const std::vector<Image>& renders) {
    return combined_mean(nullptr, 0, renders);
}

MeanEstimate mean_with_earlier(const Image& earlier, int earlier_count, const std::vector<Image>& renders) {
    if (earlier_count < 1) throw std::invalid_argument("an earlier mean stands for at least 1 render");
    return combined_mean(&earlier, earlier_count, renders);
}

}  // namespace volguide
