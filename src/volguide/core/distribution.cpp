#include "volguide/core/distribution.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "volguide/core/math.h"

namespace volguide {

DiscreteDistribution::DiscreteDistribution(std::span<const float> weights) {
    if (weights.empty()) throw std::invalid_argument("discrete distribution: no entries");
    double sum = 0.0;
    for (float w : weights) {
        if (!(w >= 0.f) || !std::isfinite(w)) throw std::invalid_argument("discrete distribution: bad weight");
        sum += w;
    }
    if (!(sum > 0.0)) throw std::invalid_argument("discrete distribution: all weights are zero");
    sum_ = sum;
    pmf_.resize(weights.size());
    cdf_.resize(weights.size());
    double acc = 0.0;
    for (size_t i = 0; i < weights.size(); ++i) {
        pmf_[i] = float(weights[i] / sum);
        acc += weights[i] / sum;
        cdf_[i] = acc;
    }
    cdf_.back() = 1.0;
}

size_t DiscreteDistribution::sample(float u) const {
    size_t i = size_t(std::upper_bound(cdf_.begin(), cdf_.end(), double(u)) - cdf_.begin());
    i = std::min(i, cdf_.size() - 1);
    while (pmf_[i] == 0.f && i > 0) --i;  // never return a zero-probability entry
    while (pmf_[i] == 0.f && i + 1 < pmf_.size()) ++i;
    return i;
}

size_t DiscreteDistribution::sample_reuse(float& u) const {
    size_t i = sample(u);
    double lo = i == 0 ? 0.0 : cdf_[i - 1];
    double width = cdf_[i] - lo;
    u = width > 0.0 ? float(std::clamp((double(u) - lo) / width, 0.0, double(OneMinusEpsilon))) : 0.f;
    return i;
}

}  // namespace volguide
