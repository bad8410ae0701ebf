#pragma once
// Mitsuba 3's reconstruction filters (rfilter plugins): box, tent and gaussian. The film splats each
// sample to the pixels whose centres lie within radius() on both axes with weight
// eval(dx) * eval(dy) and divides by the accumulated weight (hdrfilm semantics).
#include <cmath>
#include <memory>

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
    // Half-open, as Mitsuba 3 (the film bypasses eval for the box and uses the pixel a sample falls in).
    float eval(float x) const override { return x >= -0.5f && x < 0.5f ? 1.f : 0.f; }
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

// Mitchell-Netravali cubic of radius 2 with parameters B and C (default 1/3 each; Mitsuba reads
// "B" and "C"). Negative lobes: pixels are still normalised by the sum of (signed) weights.
class MitchellFilter final : public ReconstructionFilter {
  public:
    MitchellFilter(float b, float c, const char* name = "mitchell");
    explicit MitchellFilter(const Properties& props);
    float eval(float x) const override;
    std::string to_string() const override;

  private:
    float b_, c_;
    const char* name_;
};

// Catmull-Rom: the Mitchell-Netravali cubic with B = 0, C = 1/2 (no parameters).
inline std::shared_ptr<MitchellFilter> make_catmull_rom() {
    return std::make_shared<MitchellFilter>(0.f, 0.5f, "catmullrom");
}

// Lanczos-windowed sinc with `lobes` lobes (default 3), radius = lobes.
class LanczosFilter final : public ReconstructionFilter {
  public:
    explicit LanczosFilter(int lobes = 3);
    explicit LanczosFilter(const Properties& props);
    float eval(float x) const override;
    std::string to_string() const override;
};

// Mitsuba's border size of a filter: how many pixels outside the image a sample can lie and still
// reach the image (used with hdrfilm's sample_border).
inline int filter_border_size(const ReconstructionFilter& f) {
    return int(std::ceil(f.radius() - 0.5f));
}

}  // namespace volguide
