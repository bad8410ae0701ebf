#include "volguide/integrators/guided/estimates/continuation_stats.h"

#include <algorithm>
#include <cmath>

namespace volguide {

namespace {
constexpr double kPixelScale = 65536.0;          // 2^16: x^2 <= 1e10 per sample, 10^4 such fit in 2^63
constexpr double kPixelClamp = 1e5;
}  // namespace

int continuation_direction_bin(const Vec3f& w) {
    const float ax = std::abs(w.x), ay = std::abs(w.y), az = std::abs(w.z);
    if (ax >= ay && ax >= az) return w.x >= 0.f ? 0 : 1;
    if (ay >= az) return w.y >= 0.f ? 2 : 3;
    return w.z >= 0.f ? 4 : 5;
}

ContinuationMoments& ContinuationMoments::operator+=(const ContinuationMoments& o) {
    n += o.n;
    sum += o.sum;
    sum_sq += o.sum_sq;
    cost += o.cost;
    return *this;
}

ContinuationStatistics::ContinuationStatistics(size_t cells)
    : cells_(cells), moments_(size_t(kContinuationStages) * cells * size_t(kContinuationDirectionBins)) {}

void ContinuationStatistics::add_point(ContinuationStage stage, size_t cell, int bin, double y, uint64_t cost) {
    if (cell >= cells_ || !std::isfinite(y)) return;
    ContinuationMoments& m = moments_[index(stage, cell, bin)];
    ++m.n;
    m.sum.add(y);
    m.sum_sq.add(y * y);
    m.cost += cost;
}

void ContinuationStatistics::add_camera_sample(uint64_t cost, int branches) {
    ++camera_samples_;
    cost_ += cost;
    branches_ += uint64_t(std::max(branches, 0));
}

void ContinuationStatistics::clear() {
    std::fill(moments_.begin(), moments_.end(), ContinuationMoments());
    camera_samples_ = cost_ = branches_ = 0;
}

ContinuationStatistics& ContinuationStatistics::operator+=(const ContinuationStatistics& o) {
    if (cells_ == 0) *this = ContinuationStatistics(o.cells_);
    if (o.cells_ == cells_)
        for (size_t i = 0; i < moments_.size(); ++i) moments_[i] += o.moments_[i];
    camera_samples_ += o.camera_samples_;
    cost_ += o.cost_;
    branches_ += o.branches_;
    return *this;
}

PixelMoments::PixelMoments(int width, int height)
    : width_(width),
      height_(height),
      sum_(new std::atomic<int64_t>[size_t(width) * size_t(height)]),
      sum_sq_(new std::atomic<int64_t>[size_t(width) * size_t(height)]),
      count_(new std::atomic<uint32_t>[size_t(width) * size_t(height)]) {
    clear();
}

long PixelMoments::pixel(Point2f film_uv) const {
    const float fx = std::floor(film_uv.x * float(width_)), fy = std::floor(film_uv.y * float(height_));
    if (!(fx >= 0.f && fy >= 0.f && fx < float(width_) && fy < float(height_))) return -1;
    return long(fy) * long(width_) + long(fx);
}

void PixelMoments::add(long pixel, double x) {
    if (pixel < 0 || pixel >= long(width_) * long(height_) || !std::isfinite(x)) return;
    x = std::clamp(x, 0.0, kPixelClamp);
    const size_t p = size_t(pixel);
    sum_[p].fetch_add(int64_t(std::nearbyint(x * kPixelScale)), std::memory_order_relaxed);
    sum_sq_[p].fetch_add(int64_t(std::nearbyint(x * x * kPixelScale)), std::memory_order_relaxed);
    count_[p].fetch_add(1, std::memory_order_relaxed);
}

PixelMoments::Pixel PixelMoments::at(size_t p) const {
    Pixel px;
    px.n = double(count_[p].load(std::memory_order_relaxed));
    px.sum = double(sum_[p].load(std::memory_order_relaxed)) / kPixelScale;
    px.sum_sq = double(sum_sq_[p].load(std::memory_order_relaxed)) / kPixelScale;
    return px;
}

float PixelMoments::Pixel::correction(double prior) const { return float((prior + sum) / (prior + n)); }

void PixelMoments::clear() {
    for (size_t p = 0; p < size_t(width_) * size_t(height_); ++p) {
        sum_[p].store(0, std::memory_order_relaxed);
        sum_sq_[p].store(0, std::memory_order_relaxed);
        count_[p].store(0, std::memory_order_relaxed);
    }
}

ContinuationSnapshot ContinuationSnapshot::from(const ContinuationStatistics& stats, const PixelMoments& pixels,
                                                const EarsSettings& settings, double unsplit_cost) {
    ContinuationSnapshot snap;
    snap.cells_ = stats.cells();
    snap.table_.resize(size_t(kContinuationStages) * snap.cells_ * size_t(kContinuationDirectionBins));
    for (int stage = 0; stage < kContinuationStages; ++stage)
        for (size_t cell = 0; cell < snap.cells_; ++cell)
            for (int bin = 0; bin < kContinuationDirectionBins; ++bin) {
                const ContinuationMoments& m = stats.moments(ContinuationStage(stage), cell, bin);
                if (m.n < std::max<uint64_t>(settings.min_samples, 2) || m.cost == 0) continue;
                const double n = double(m.n), mean = m.sum.value() / n, m2 = std::max(0.0, m.sum_sq.value() / n);
                const double cost = double(m.cost) / n;
                Cell& c = snap.table_[(size_t(stage) * snap.cells_ + cell) * size_t(kContinuationDirectionBins) +
                                      size_t(bin)];
                c.r = float(std::sqrt(m2 / cost));
                c.s = float(std::sqrt(std::max(0.0, m2 - mean * mean) / cost));
                ++snap.learned_;
                snap.learned_surface_ += ContinuationStage(stage) == ContinuationStage::Surface;
            }
    const uint64_t samples = stats.camera_samples();
    snap.image_cost_ = samples ? double(stats.cost()) / double(samples) : 0.0;
    snap.learn_pixels(pixels, settings.pixel_prior);
    if (snap.image_variance_ > 0.0 && snap.image_cost_ > 0.0)
        snap.image_factor_ = float(std::sqrt(snap.image_cost_ / snap.image_variance_));
    // Cost budget -> branches: the mean cost of a branch measured so far (splits late in a path make
    // cheaper branches, so more of them fit).
    const double per_branch = stats.branches() ? double(stats.cost()) / double(stats.branches()) : 0.0;
    double budget = settings.min_budget;
    if (settings.fixed_budget >= 1.f)
        budget = settings.fixed_budget;
    else if (unsplit_cost > 0.0 && per_branch > 0.0)
        budget = std::max(budget, double(settings.budget_factor) * unsplit_cost / per_branch);
    snap.budget_ = float(std::min(std::floor(budget), double(settings.max_branches)));
    return snap;
}

// The learned estimate I' = I c of each pixel: c = (k + sum x) / (k + n), the mean of x = X / I shrunk
// towards 1 (I itself) by k prior samples; and the image's relative variance per sample, the mean over
// the pixels with n >= 2 of var(x) / c^2 = var(X) / I'^2. Relative to I alone, pixels whose I is far too
// dark (x ~ 100 where the field misses light diffused through a dense medium) dominated V.
void ContinuationSnapshot::learn_pixels(const PixelMoments& pixels, double prior) {
    const size_t count = size_t(pixels.width()) * size_t(pixels.height());
    pixel_correction_.assign(count, 1.f);
    double total = 0.0;
    size_t used = 0;
    for (size_t p = 0; p < count; ++p) {
        const PixelMoments::Pixel px = pixels.at(p);
        const float c = px.correction(prior);
        pixel_correction_[p] = c;
        if (px.n < 2.0 || !(c > 0.f)) continue;
        const double var = std::max(0.0, (px.sum_sq - px.sum * px.sum / px.n) / (px.n - 1.0));
        total += var / (double(c) * double(c));
        ++used;
    }
    image_variance_ = used > 0 ? total / double(used) : -1.0;
}

float ContinuationSnapshot::factor(ContinuationStage stage, size_t cell, int bin, float relative_weight) const {
    if (cell >= cells_ || !(image_factor_ > 0.f) || !(relative_weight >= 0.f) || !std::isfinite(relative_weight))
        return -1.f;
    const Cell& c = table_[(size_t(stage) * cells_ + cell) * size_t(kContinuationDirectionBins) + size_t(bin)];
    if (c.r < 0.f) return -1.f;
    // Roulette by the second moment (what RR adds to the variance is (1/q - 1) M2); splitting by the
    // variance (what n copies take from it is (1 - 1/n) Var), and only where both ask for it.
    const float q_r = relative_weight * c.r * image_factor_;
    if (q_r <= 1.f) return q_r;
    const float q_s = relative_weight * c.s * image_factor_;
    return q_s >= 1.f ? q_s : 1.f;
}

}  // namespace volguide
