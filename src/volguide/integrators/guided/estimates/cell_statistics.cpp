#include "volguide/integrators/guided/estimates/cell_statistics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace volguide {

namespace {
constexpr double kFixedScale = 4294967296.0;  // 2^32
constexpr double kMaxTerm = 1e15;
constexpr double kTwo64 = 18446744073709551616.0;
constexpr double kPixelScale = 65536.0;  // 2^16: x^2 <= 1e10 per sample, 10^4 such fit in 2^63
constexpr double kPixelClamp = 1e5;
}  // namespace

int continuation_direction_bin(const Vec3f& w) {
    const float ax = std::abs(w.x), ay = std::abs(w.y), az = std::abs(w.z);
    if (ax >= ay && ax >= az) return w.x >= 0.f ? 0 : 1;
    if (ay >= az) return w.y >= 0.f ? 2 : 3;
    return w.z >= 0.f ? 4 : 5;
}

void ExactSum::add_words(uint64_t hi, uint64_t lo) {
    lo_ += lo;
    hi_ += hi + (lo_ < lo ? 1 : 0);
}

void ExactSum::add(double term) {
    if (!(term > 0.0)) return;  // zero, negative rounding noise, NaN
    const double t = std::floor(std::min(term, kMaxTerm) * kFixedScale);  // < 2^82
    const double hi = std::floor(t / kTwo64);
    add_words(uint64_t(hi), uint64_t(t - hi * kTwo64));  // both parts exact in double
}

ExactSum& ExactSum::operator+=(const ExactSum& o) {
    add_words(o.hi_, o.lo_);
    return *this;
}

double ExactSum::value() const { return (double(hi_) * kTwo64 + double(lo_)) / kFixedScale; }

DecisionMoments& DecisionMoments::operator+=(const DecisionMoments& o) {
    for (size_t k = 0; k < m.size(); ++k) m[k] += o.m[k];
    current += o.current;
    count += o.count;
    return *this;
}

ContinuationMoments& ContinuationMoments::operator+=(const ContinuationMoments& o) {
    n += o.n;
    sum += o.sum;
    sum_sq += o.sum_sq;
    cost += o.cost;
    return *this;
}

CellStatistics::CellStatistics(size_t cells)
    : cells_(cells),
      decisions_(cells * size_t(kDecisionKinds)),
      continuations_(size_t(kContinuationStages) * cells * size_t(kContinuationDirectionBins)) {}

void CellStatistics::add_decision(DecisionKind d, size_t cell, double s2, float q_cur, float p_u, float p_g) {
    if (cell >= cells_ || !(q_cur > 0.f) || !std::isfinite(s2)) return;
    DecisionMoments& m = decisions_[cell * size_t(kDecisionKinds) + size_t(d)];
    ++m.count;
    if (!(s2 > 0.0)) return;
    m.current.add(s2);
    for (size_t k = 0; k < kSelectionShares.size(); ++k) {
        const double a = kSelectionShares[k];
        const double q = (1.0 - a) * double(p_u) + a * double(p_g);
        // A share whose mixture cannot sample what was sampled: infinite second moment (clamped).
        m.m[k].add(q > 0.0 ? s2 * double(q_cur) / q : kMaxTerm);
    }
}

void CellStatistics::add_continuation(ContinuationStage stage, size_t cell, int bin, double y, uint64_t cost) {
    if (cell >= cells_ || !std::isfinite(y)) return;
    ContinuationMoments& m = continuations_[index(stage, cell, bin)];
    ++m.n;
    m.sum.add(y);
    m.sum_sq.add(y * y);
    m.cost += cost;
}

void CellStatistics::add_camera_sample(double s2, uint64_t cost, uint64_t unrecorded, int branches) {
    ++camera_samples_;
    if (std::isfinite(s2)) camera_moment_.add(s2);
    cost_ += cost;
    unrecorded_ += unrecorded;
    branches_ += uint64_t(std::max(branches, 0));
}

void CellStatistics::clear() { *this = CellStatistics(cells_); }

CellStatistics& CellStatistics::operator+=(const CellStatistics& o) {
    if (cells_ == 0) *this = CellStatistics(o.cells_);
    if (o.cells_ != cells_) throw std::logic_error("CellStatistics: different cell counts");
    for (size_t i = 0; i < decisions_.size(); ++i) decisions_[i] += o.decisions_[i];
    for (size_t i = 0; i < continuations_.size(); ++i) continuations_[i] += o.continuations_[i];
    camera_samples_ += o.camera_samples_;
    camera_moment_ += o.camera_moment_;
    cost_ += o.cost_;
    unrecorded_ += o.unrecorded_;
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

}  // namespace volguide
