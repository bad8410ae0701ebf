#pragma once
// Mitsuba 3's reconstruction filters (rfilter plugins): box, tent and gaussian. The film splats each
// sample to the pixels whose centres lie within radius() on both axes with weight
// eval(dx) * eval(dy) and divides by the accumulated weight (hdrfilm semantics).
#include <cmath>

#include "volguide/core/properties.h"
#include "volguide/render/sensor.h"

namespace volguide {

// Wider filters are rejected (the film's splatting handles at most 2 * 16 + 1 taps per axis).
inline constexpr float kMaxFilterRadius = 16.f;

// One pixel wide: every sample counts, with weight 1, for the pixel it falls in.
class BoxFilter final : public ReconstructionFilter {
public:
    BoxFilter() { radius_ = 0.5f; }
    explicit BoxFilter(const Properties& props) : BoxFilter() {}
    float eval(float x) const override { return std::abs(x) <= radius_ ? 1.f : 0.f; }
    std::string to_string() const override { return "box"; }
};

// Triangle of the given radius (Mitsuba's `radius`, default 1).
class TentFilter final : public ReconstructionFilter {
public:
    explicit TentFilter(float radius);
    explicit TentFilter(const Properties& props);
    float eval(float x) const override { return std::max(0.f, 1.f - std::abs(x) * inv_radius_); }
    std::string to_string() const override;

private:
    float inv_radius_;
};

// Gaussian of standard deviation `stddev` (default 0.5) cut off at 4 stddev, shifted down so that
// it reaches zero at the cut-off: max(0, exp(-x^2 / (2 stddev^2)) - exp(-8)), as Mitsuba 3.
class GaussianFilter final : public ReconstructionFilter {
public:
    explicit GaussianFilter(float stddev = 0.5f);
    explicit GaussianFilter(const Properties& props);
    float eval(float x) const override { return std::max(0.f, std::exp(alpha_ * x * x) - bias_); }
    float stddev() const { return stddev_; }
    std::string to_string() const override;

private:
    float stddev_, alpha_, bias_;
};

// Mitsuba's border size of a filter: how many pixels outside the image a sample can lie and still
// reach the image (used with hdrfilm's sample_border).
inline int filter_border_size(const ReconstructionFilter& f) { return int(std::ceil(f.radius() - 0.5f)); }

}  // namespace volguide
