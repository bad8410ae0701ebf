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
    if (radius_ > kMaxFilterRadius) props.fail_at("radius", "tent filter radius above {} pixels is not supported", kMaxFilterRadius);
}

std::string TentFilter::to_string() const { return fmt::format("tent[radius={}]", radius_); }

GaussianFilter::GaussianFilter(float stddev) : stddev_(stddev) {
    radius_ = 4.f * stddev;
    alpha_ = -1.f / (2.f * stddev * stddev);
    bias_ = std::exp(alpha_ * radius_ * radius_);
}

GaussianFilter::GaussianFilter(const Properties& props) : GaussianFilter(props.get_float("stddev", 0.5f)) {
    if (!(stddev_ > 0.f) || !std::isfinite(stddev_))
        props.fail_at("stddev", "gaussian filter stddev must be positive and finite, got {}", stddev_);
    if (radius_ > kMaxFilterRadius)
        props.fail_at("stddev", "gaussian filter radius 4 * stddev above {} pixels is not supported", kMaxFilterRadius);
}

std::string GaussianFilter::to_string() const { return fmt::format("gaussian[stddev={}]", stddev_); }

}  // namespace volguide
