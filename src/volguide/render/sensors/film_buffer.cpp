#include "volguide/render/sensors/film_buffer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "volguide/render/sensors/rfilters.h"

namespace volguide {

Splatter::Splatter(const ReconstructionFilter& filter, int film_width, int film_height)
    : filter_(&filter),
      box_(dynamic_cast<const BoxFilter*>(&filter) != nullptr),
      radius_(filter.radius()),
      width_(film_width),
      height_(film_height) {}

PixelRect Splatter::footprint(const PixelRect& s) const {
    // A sample at p reaches pixel i when |i + 0.5 - p| <= radius; one extra pixel of slack on each
    // side covers rounding in splat().
    int reach = box_ ? 0 : int(std::ceil(radius_)) + 1;
    PixelRect r{s.x0 - reach, s.y0 - reach, s.x1 + reach, s.y1 + reach};
    r.x0 = std::max(r.x0, 0);
    r.y0 = std::max(r.y0, 0);
    r.x1 = std::min(r.x1, width_);
    r.y1 = std::min(r.y1, height_);
    return r;
}

TileBuffer::TileBuffer(const Splatter& splatter, PixelRect rect, bool second_moment)
    : splatter_(&splatter), rect_(rect), second_moment_(second_moment) {
    size_t n = rect.empty() ? 0 : size_t(rect.width()) * rect.height();
    weight_.assign(n, 0.f);
    sum_.assign(n, Color3(0.f));
    if (second_moment) sum2_.assign(n, Color3(0.f));
}

void TileBuffer::splat(Point2f pos, const Color3& value) {
    const Color3 value2 = second_moment_ ? value * value : Color3(0.f);
    auto add = [&](int x, int y, float w) {
        size_t k = size_t(y - rect_.y0) * rect_.width() + size_t(x - rect_.x0);
        weight_[k] += w;
        sum_[k] += value * w;
        if (second_moment_) sum2_[k] += value2 * w;
    };
    if (splatter_->is_box()) {
        // Mitsuba's box filter: the sample counts for the pixel it falls in, with weight 1.
        int x = int(std::floor(pos.x)), y = int(std::floor(pos.y));
        if (x >= rect_.x0 && x < rect_.x1 && y >= rect_.y0 && y < rect_.y1) add(x, y, 1.f);
        return;
    }
    // Relative to pixel centres: pixel i is affected when |i - q| <= radius.
    const float r = splatter_->radius();
    const float qx = pos.x - 0.5f, qy = pos.y - 0.5f;
    const int lo_x = std::max(int(std::ceil(qx - r)), rect_.x0),
              hi_x = std::min(int(std::floor(qx + r)), rect_.x1 - 1);
    const int lo_y = std::max(int(std::ceil(qy - r)), rect_.y0),
              hi_y = std::min(int(std::floor(qy + r)), rect_.y1 - 1);
    if (lo_x > hi_x || lo_y > hi_y) return;
    constexpr int kMaxTaps = 64;
    float wx[kMaxTaps], wy[kMaxTaps];
    const int nx = std::min(hi_x - lo_x + 1, kMaxTaps), ny = std::min(hi_y - lo_y + 1, kMaxTaps);
    const ReconstructionFilter& f = splatter_->filter();
    for (int i = 0; i < nx; ++i) wx[i] = f.eval(float(lo_x + i) - qx);
    for (int j = 0; j < ny; ++j) wy[j] = f.eval(float(lo_y + j) - qy);
    for (int j = 0; j < ny; ++j) {
        if (wy[j] == 0.f) continue;
        for (int i = 0; i < nx; ++i)
            if (float w = wx[i] * wy[j]; w != 0.f) add(lo_x + i, lo_y + j, w);
    }
}

FilmBuffer::FilmBuffer(int width, int height, bool second_moment)
    : width_(width), height_(height), second_moment_(second_moment) {
    size_t n = size_t(width) * height;
    weight_.assign(n, 0.0);
    sum_.assign(3 * n, 0.0);
    if (second_moment) sum2_.assign(3 * n, 0.0);
}

void FilmBuffer::restore(FilmSums sums) {
    if (sums.weight.size() != weight_.size() || sums.sum.size() != sum_.size() || sums.sum2.size() != sum2_.size())
        throw std::invalid_argument("film sums of another film size or variance setting");
    weight_ = std::move(sums.weight);
    sum_ = std::move(sums.sum);
    sum2_ = std::move(sums.sum2);
}

void FilmBuffer::add(const TileBuffer& tile) {
    const PixelRect& r = tile.rect_;
    for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) {
            size_t k = size_t(y - r.y0) * r.width() + size_t(x - r.x0);
            size_t p = size_t(y) * width_ + x;
            weight_[p] += tile.weight_[k];
            for (int c = 0; c < 3; ++c) sum_[3 * p + c] += tile.sum_[k][c];
            if (second_moment_ && tile.second_moment_)
                for (int c = 0; c < 3; ++c) sum2_[3 * p + c] += tile.sum2_[k][c];
        }
}

Image FilmBuffer::mean() const {
    Image img(width_, height_);
    for (size_t p = 0; p < weight_.size(); ++p) {
        if (weight_[p] == 0.0) continue;
        double inv = 1.0 / weight_[p];
        img.pixels[p] =
            Color3(float(sum_[3 * p] * inv), float(sum_[3 * p + 1] * inv), float(sum_[3 * p + 2] * inv));
    }
    return img;
}

Image FilmBuffer::variance() const {
    if (!second_moment_) return {};
    Image img(width_, height_);
    for (size_t p = 0; p < weight_.size(); ++p) {
        if (weight_[p] == 0.0) continue;
        double inv = 1.0 / weight_[p];
        for (int c = 0; c < 3; ++c) {
            double m = sum_[3 * p + c] * inv;
            img.pixels[p][c] = float(std::max(0.0, sum2_[3 * p + c] * inv - m * m));
        }
    }
    return img;
}

}  // namespace volguide
