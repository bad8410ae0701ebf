#include "volguide/render/emitters/bilinear_warp.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "volguide/core/math.h"

namespace volguide {
namespace {

// Inverts the CDF of the density proportional to (1 - x) a + x b on [0, 1] (a, b >= 0).
float sample_linear(float u, float a, float b) {
    if (a + b <= 0.f) return u;  // zero density line (measure zero): any point will do
    if (u == 0.f) return 0.f;
    // Numerically stable root of a x + (b - a) x^2 / 2 = u (a + b) / 2.
    const float x = u * (a + b) / (a + std::sqrt(lerp(u, a * a, b * b)));
    return std::min(x, OneMinusEpsilon);
}

}  // namespace

BilinearWarp2D::BilinearWarp2D(std::vector<float> values, int nx, int ny)
    : values_(std::move(values)), nx_(nx), ny_(ny) {
    if (nx < 2 || ny < 2 || values_.size() != size_t(nx) * size_t(ny))
        throw std::invalid_argument("bilinear warp: need at least 2x2 vertex values");
    for (float v : values_)
        if (!(v >= 0.f) || !std::isfinite(v)) throw std::invalid_argument("bilinear warp: bad value");

    const int cx = nx - 1, cy = ny - 1;
    std::vector<float> row_mass(cy, 0.f), cell_mass(cx);
    cols_.resize(cy);
    double total = 0.0;
    for (int j = 0; j < cy; ++j) {
        double row = 0.0;
        for (int i = 0; i < cx; ++i) {
            const float* v0 = &values_[size_t(j) * nx + i];
            const float* v1 = v0 + nx;
            // The integral of a bilinear patch is the mean of its corners (times the cell area).
            cell_mass[i] = 0.25f * (v0[0] + v0[1] + v1[0] + v1[1]);
            row += cell_mass[i];
        }
        row_mass[j] = float(row);
        if (row > 0.0) cols_[j] = DiscreteDistribution(cell_mass);
        total += row;
    }
    norm_ = total / (double(cx) * double(cy));
    if (norm_ > 0.0) {
        inv_norm_ = float(1.0 / norm_);
        rows_ = DiscreteDistribution(row_mass);
    }
}

float BilinearWarp2D::cell_value(int i, int j, float fx, float fy) const {
    const float* v0 = &values_[size_t(j) * nx_ + i];
    const float* v1 = v0 + nx_;
    return lerp(fy, lerp(fx, v0[0], v0[1]), lerp(fx, v1[0], v1[1]));
}

std::pair<Point2f, float> BilinearWarp2D::sample(Point2f u) const {
    if (!valid()) return {Point2f(0.f, 0.f), 0.f};
    const int j = int(rows_.sample_reuse(u.y));
    const int i = int(cols_[j].sample_reuse(u.x));

    const float* v0 = &values_[size_t(j) * nx_ + i];
    const float* v1 = v0 + nx_;
    const float fy = sample_linear(u.y, v0[0] + v0[1], v1[0] + v1[1]);
    const float fx = sample_linear(u.x, lerp(fy, v0[0], v1[0]), lerp(fy, v0[1], v1[1]));

    const Point2f p{std::min((i + fx) / float(nx_ - 1), OneMinusEpsilon),
                    std::min((j + fy) / float(ny_ - 1), OneMinusEpsilon)};
    return {p, cell_value(i, j, fx, fy) * inv_norm_};
}

float BilinearWarp2D::pdf(Point2f p) const {
    if (!valid()) return 0.f;
    const float x = std::clamp(p.x, 0.f, 1.f) * float(nx_ - 1);
    const float y = std::clamp(p.y, 0.f, 1.f) * float(ny_ - 1);
    const int i = std::min(int(x), nx_ - 2), j = std::min(int(y), ny_ - 2);
    return cell_value(i, j, x - i, y - j) * inv_norm_;
}

}  // namespace volguide
