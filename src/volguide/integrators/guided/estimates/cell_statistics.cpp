#include "volguide/integrators/guided/estimates/cell_statistics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "volguide/core/bytes.h"

namespace volguide {

namespace {
constexpr double kFixedScale = 4294967296.0;  // 2^32
constexpr double kMaxTerm = 1e15;
constexpr double kTwo64 = 18446744073709551616.0;
constexpr double kPixelScale = 65536.0;  // 2^16: x^2 <= 1e10 per sample, 10^4 such fit in 2^63
constexpr double kPixelClamp = 1e5;
constexpr uint32_t kStatisticsMagic = 0x53434756;  // "VGCS"
constexpr uint32_t kStatisticsVersion = 2;
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

ExactSum ExactSum::from_words(uint64_t hi, uint64_t lo) {
    ExactSum s;
    s.hi_ = hi;
    s.lo_ = lo;
    return s;
}

DecisionMoments& DecisionMoments::operator+=(const DecisionMoments& o) {
    for (size_t k = 0; k < kShares; ++k) {
        m[k] += o.m[k];
        after[k] += o.after[k];
    }
    current += o.current;
    current_after += o.current_after;
    own += o.own;
    own_unguided += o.own_unguided;
    count += o.count;
    unguided += o.unguided;
    unguided_m += o.unguided_m;
    unguided_own += o.unguided_own;
    unguided_after += o.unguided_after;
    return *this;
}

ContinuationChoiceMoments& ContinuationChoiceMoments::operator+=(const ContinuationChoiceMoments& o) {
    known_points += o.known_points;
    for (int r = 0; r < kContinuationRules; ++r) {
        known_m[size_t(r)] += o.known_m[size_t(r)];
        known_c[size_t(r)] += o.known_c[size_t(r)];
    }
    other_points += o.other_points;
    other_m += o.other_m;
    other_c += o.other_c;
    current_m += o.current_m;
    current_c += o.current_c;
    return *this;
}

double continuation_second_moment(double b, double a2, double b2, double q) {
    if (!(q > 0.0)) return kMaxTerm;
    const double f = std::floor(q);
    const double pairs = f * (2.0 * q - f - 1.0);  // E[n (n - 1)] of n = floor(q + u)
    return b * b * (a2 / q + std::max(0.0, pairs) * b2 / (q * q));
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
      choices_(cells),
      continuations_(size_t(kContinuationStages) * cells * size_t(kContinuationDirectionBins)) {}

void CellStatistics::add_decision(DecisionKind d, const DecisionSample& s) {
    if (s.cell >= cells_ || !std::isfinite(s.s2)) return;
    DecisionMoments& m = decisions_[s.cell * size_t(kDecisionKinds) + size_t(d)];
    if (!s.mixture) {
        ++m.unguided;
        m.unguided_m.add(s.s2);
        m.unguided_own.add(s.own);
        m.unguided_after.add(s.after);
        return;
    }
    if (!(s.q_cur > 0.f)) return;
    ++m.count;
    m.current.add(s.s2);
    m.current_after.add(s.after);
    m.own.add(s.own);
    m.own_unguided.add(s.own_unguided);
    for (size_t k = 0; k < kShares; ++k) {
        const double a = kSelectionShares[k];
        const double q = (1.0 - a) * double(s.p_u) + a * double(s.p_g);
        // A share whose mixture cannot sample what was sampled: infinite second moment (clamped), and
        // what followed would not have happened (no cost).
        m.m[k].add(q > 0.0 ? s.s2 * double(s.q_cur) / q : (s.s2 > 0.0 ? kMaxTerm : 0.0));
        m.after[k].add(s.after * q / double(s.q_cur));
    }
}

void CellStatistics::add_continuation_point(const ContinuationSample& s) {
    if (s.cell >= cells_ || !std::isfinite(s.a2) || !std::isfinite(s.b2) || !std::isfinite(s.b)) return;
    ContinuationChoiceMoments& c = choices_[s.cell];
    // A point decided with q_cur < 1 survived with probability q_cur: it stands for 1 / q_cur points.
    const double weight = s.q_cur < 1.f ? 1.0 / double(std::max(s.q_cur, 1e-6f)) : 1.0;
    auto moment = [&](double q) { return weight * continuation_second_moment(s.b, s.a2, s.b2, q); };
    auto cost = [&](double q) { return weight * q * s.copy_cost; };
    c.current_m.add(moment(s.q_cur));
    c.current_c.add(cost(s.q_cur));
    if (s.guided_known) {
        const std::array<double, kContinuationRules> q = {s.q_unguided, std::min(s.q_guided, 1.f), s.q_guided};
        c.known_points.add(weight);
        for (int r = 0; r < kContinuationRules; ++r) {
            c.known_m[size_t(r)].add(moment(q[size_t(r)]));
            c.known_c[size_t(r)].add(cost(q[size_t(r)]));
        }
    } else {
        c.other_points.add(weight);
        c.other_m.add(moment(s.q_unguided));
        c.other_c.add(cost(s.q_unguided));
    }
}

void CellStatistics::add_continuation(ContinuationStage stage, size_t cell, int bin, double y, double cost) {
    if (cell >= cells_ || !std::isfinite(y)) return;
    ContinuationMoments& m = continuations_[index(stage, cell, bin)];
    ++m.n;
    m.sum.add(y);
    m.sum_sq.add(y * y);
    m.cost.add(cost);
}

void CellStatistics::add_camera_sample(double s2, double cost, int branches, const SampleOverhead& overhead) {
    ++camera_samples_;
    if (std::isfinite(s2)) camera_moment_.add(s2);
    cost_.add(cost);
    recording_.add(overhead.recording);
    policy_.add(overhead.policy);
    branches_ += uint64_t(std::max(branches, 0));
}

void CellStatistics::add_control_sample(double s2, double cost) {
    ++control_samples_;
    if (std::isfinite(s2)) control_moment_.add(s2);
    control_cost_.add(cost);
}

double CellStatistics::continuation_cost_ratio() const {
    uint64_t copies = 0;
    double after = 0.0;
    for (const ContinuationMoments& m : continuations_) {
        copies += m.n;
        after += m.cost.value();
    }
    if (copies == 0 || !(after > 0.0) || camera_samples_ == 0) return 0.0;
    return (cost_.value() / double(camera_samples_)) / (after / double(copies));
}

void CellStatistics::clear() { *this = CellStatistics(cells_); }

CellStatistics& CellStatistics::operator+=(const CellStatistics& o) {
    if (cells_ == 0) *this = CellStatistics(o.cells_);
    if (o.cells_ != cells_) throw std::logic_error("CellStatistics: different cell counts");
    for (size_t i = 0; i < decisions_.size(); ++i) decisions_[i] += o.decisions_[i];
    for (size_t i = 0; i < choices_.size(); ++i) choices_[i] += o.choices_[i];
    for (size_t i = 0; i < continuations_.size(); ++i) continuations_[i] += o.continuations_[i];
    camera_samples_ += o.camera_samples_;
    camera_moment_ += o.camera_moment_;
    cost_ += o.cost_;
    recording_ += o.recording_;
    policy_ += o.policy_;
    branches_ += o.branches_;
    control_samples_ += o.control_samples_;
    control_moment_ += o.control_moment_;
    control_cost_ += o.control_cost_;
    return *this;
}

namespace {

void put(ByteWriter& w, const ExactSum& s) {
    w.u64(s.hi());
    w.u64(s.lo());
}
ExactSum get_sum(ByteReader& r) {
    const uint64_t hi = r.u64("a sum");
    return ExactSum::from_words(hi, r.u64("a sum"));
}

// Every member of the three records in one order, for writing and reading alike.
// (M: the record, const for writing.)
template <class M, class Sum, class Count>
void each_decision(M& m, Sum&& sum, Count&& count) {
    for (size_t k = 0; k < kShares; ++k) {
        sum(m.m[k]);
        sum(m.after[k]);
    }
    sum(m.current);
    sum(m.current_after);
    sum(m.own);
    sum(m.own_unguided);
    count(m.count);
    count(m.unguided);
    sum(m.unguided_m);
    sum(m.unguided_own);
    sum(m.unguided_after);
}
template <class M, class Sum>
void each_choice(M& c, Sum&& sum) {
    sum(c.known_points);
    for (int r = 0; r < kContinuationRules; ++r) {
        sum(c.known_m[size_t(r)]);
        sum(c.known_c[size_t(r)]);
    }
    for (auto* s : {&c.other_points, &c.other_m, &c.other_c, &c.current_m, &c.current_c}) sum(*s);
}
template <class M, class Sum, class Count>
void each_continuation(M& m, Sum&& sum, Count&& count) {
    count(m.n);
    sum(m.sum);
    sum(m.sum_sq);
    sum(m.cost);
}

}  // namespace

std::string CellStatistics::serialize() const {
    ByteWriter w;
    w.u32(kStatisticsMagic);
    w.u32(kStatisticsVersion);
    w.u64(cells_);
    auto sum = [&](const ExactSum& s) { put(w, s); };
    auto count = [&](const uint64_t& c) { w.u64(c); };
    for (const DecisionMoments& m : decisions_) each_decision(m, sum, count);
    for (const ContinuationChoiceMoments& c : choices_) each_choice(c, sum);
    for (const ContinuationMoments& m : continuations_) each_continuation(m, sum, count);
    w.u64(camera_samples_);
    w.u64(branches_);
    put(w, camera_moment_);
    put(w, cost_);
    put(w, recording_);
    put(w, policy_);
    w.u64(control_samples_);
    put(w, control_moment_);
    put(w, control_cost_);
    return w.take();
}

CellStatistics CellStatistics::deserialize(const std::string& bytes) {
    ByteReader r(bytes, "cell statistics");
    if (r.u32("the magic") != kStatisticsMagic) r.fail("not", "a record of cell statistics");
    if (r.u32("the version") != kStatisticsVersion) r.fail("an unknown version of", "the record");
    const uint64_t cells = r.u64("the cell count");
    // Each cell takes at least 8 bytes per decision kind: bound the allocation by what is there.
    if (cells == 0 || cells > r.left() / 8) r.fail("a cell count beyond", "the record's size");
    CellStatistics out(static_cast<size_t>(cells));
    auto sum = [&](ExactSum& s) { s = get_sum(r); };
    auto count = [&](uint64_t& c) { c = r.u64("a count"); };
    for (DecisionMoments& m : out.decisions_) each_decision(m, sum, count);
    for (ContinuationChoiceMoments& c : out.choices_) each_choice(c, sum);
    for (ContinuationMoments& m : out.continuations_) each_continuation(m, sum, count);
    out.camera_samples_ = r.u64("the camera samples");
    out.branches_ = r.u64("the branches");
    out.camera_moment_ = get_sum(r);
    out.cost_ = get_sum(r);
    out.recording_ = get_sum(r);
    out.policy_ = get_sum(r);
    out.control_samples_ = r.u64("the control samples");
    out.control_moment_ = get_sum(r);
    out.control_cost_ = get_sum(r);
    r.finish();
    return out;
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

double PixelMoments::mean_square() const {
    double weighted = 0.0, samples = 0.0;
    for (size_t p = 0; p < size_t(width_) * size_t(height_); ++p) {
        const Pixel px = at(p);
        if (px.n < 2.0) continue;
        weighted += std::max(px.sum * px.sum - px.sum_sq, 0.0) / (px.n - 1.0);
        samples += px.n;
    }
    return samples > 0.0 ? weighted / samples : 0.0;
}

PixelMoments& PixelMoments::operator+=(const PixelMoments& o) {
    if (o.width_ != width_ || o.height_ != height_) throw std::logic_error("PixelMoments: different film sizes");
    for (size_t p = 0; p < size_t(width_) * size_t(height_); ++p) {
        sum_[p].fetch_add(o.sum_[p].load(std::memory_order_relaxed), std::memory_order_relaxed);
        sum_sq_[p].fetch_add(o.sum_sq_[p].load(std::memory_order_relaxed), std::memory_order_relaxed);
        count_[p].fetch_add(o.count_[p].load(std::memory_order_relaxed), std::memory_order_relaxed);
    }
    return *this;
}

std::string PixelMoments::serialize() const {
    ByteWriter w;
    w.u32(uint32_t(width_));
    w.u32(uint32_t(height_));
    for (size_t p = 0; p < size_t(width_) * size_t(height_); ++p) {
        w.u64(uint64_t(sum_[p].load(std::memory_order_relaxed)));
        w.u64(uint64_t(sum_sq_[p].load(std::memory_order_relaxed)));
        w.u32(count_[p].load(std::memory_order_relaxed));
    }
    return w.take();
}

void PixelMoments::restore(const std::string& bytes) {
    ByteReader r(bytes, "pixel moments");
    if (r.u32("the width") != uint32_t(width_) || r.u32("the height") != uint32_t(height_))
        r.fail("another film size in", "the record");
    for (size_t p = 0; p < size_t(width_) * size_t(height_); ++p) {
        sum_[p].store(int64_t(r.u64("a pixel sum")), std::memory_order_relaxed);
        sum_sq_[p].store(int64_t(r.u64("a pixel sum")), std::memory_order_relaxed);
        count_[p].store(r.u32("a pixel count"), std::memory_order_relaxed);
    }
    r.finish();
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
