#include "volguide/render/sensors/rfilters.h"

#include <fmt/format.h>

namespace volguide {

TentFilter::TentFilter(float radius) {
    radius_ = radius;
    inv_radius_ = 1.f / radius;
}

TentFilter::TentFilter(const Properties& props) : TentFilter(props.get_float("radius", 1.f)) {
    if (!(radius_ > 0.f) || !std::isfinite(radius_))
        props.fail_at("radius", "tent filter radius must be positive and finite, got {}", radius_);
    if (radius_ > kMaxFilterRadius)
        props.fail_at("radius", "tent filter radius above {} pixels is not supported", kMaxFilterRadius);
}

std::string TentFilter::to_string() const {
    return fmt::format("tent[radius={}]", radius_);
}

GaussianFilter::GaussianFilter(float stddev) : stddev_(stddev) {
    radius_ = 4.f * stddev;
    alpha_ = -1.f / (2.f * stddev * stddev);
    bias_ = std::exp(alpha_ * radius_ * radius_);
}

GaussianFilter::GaussianFilter(const Properties& props) : GaussianFilter(props.get_float("stddev", 0.5f)) {
    if (!(stddev_ > 0.f) || !std::isfinite(stddev_))
        props.fail_at("stddev", "gaussian filter stddev must be positive and finite, got {}", stddev_);
    if (radius_ > kMaxFilterRadius)
        props.fail_at("stddev", "gaussian filter radius 4 * stddev above {} pixels is not supported",
                      kMaxFilterRadius);
}

std::string GaussianFilter::to_string() const {
    return fmt::format("gaussian[stddev={}]", stddev_);
}

MitchellFilter::MitchellFilter(float b, float c, const char* name) : b_(b), c_(c), name_(name) {
    radius_ = 2.f;
}

MitchellFilter::MitchellFilter(const Properties& props)
    : MitchellFilter(props.get_float("B", 1.f / 3.f), props.get_float("C", 1.f / 3.f)) {
    if (!std::isfinite(b_)) props.fail_at("B", "mitchell B must be finite");
    if (!std::isfinite(c_)) props.fail_at("C", "mitchell C must be finite");
}

float MitchellFilter::eval(float x) const {
    x = std::abs(x);
    if (x >= 2.f) return 0.f;
    const float x2 = x * x, x3 = x2 * x, b = b_, c = c_;
    if (x < 1.f)
        return ((12.f - 9.f * b - 6.f * c) * x3 + (-18.f + 12.f * b + 6.f * c) * x2 + (6.f - 2.f * b)) / 6.f;
    return ((-b - 6.f * c) * x3 + (6.f * b + 30.f * c) * x2 + (-12.f * b - 48.f * c) * x +
            (8.f * b + 24.f * c)) /
           6.f;
}

std::string MitchellFilter::to_string() const {
    return std::string(name_) == "mitchell" ? fmt::format("mitchell[B={}, C={}]", b_, c_)
                                            : std::string(name_);
}

LanczosFilter::LanczosFilter(int lobes) {
    radius_ = float(lobes);
}

LanczosFilter::LanczosFilter(const Properties& props) : LanczosFilter(int(props.get_int("lobes", 3))) {
    int64_t lobes = props.get_int("lobes", 3);
    if (lobes < 1 || lobes > int64_t(kMaxFilterRadius))
        props.fail_at("lobes", "lanczos lobes must be in [1, {}], got {}", int(kMaxFilterRadius), lobes);
}

float LanczosFilter::eval(float x) const {
    x = std::abs(x);
    if (x < 1e-6f) return 1.f;
    if (x > radius_) return 0.f;
    const float a = Pi * x, b = a / radius_;
    return std::sin(a) * std::sin(b) / (a * b);
}

std::string LanczosFilter::to_string() const {
    return fmt::format("lanczos[lobes={}]", int(radius_));
}

}  // namespace volguide
