#pragma once
// Piecewise-constant discrete distribution over n entries (emitter choice, triangle choice,
// envmap rows/columns). sample_reuse() returns the index and rescales the sample so it can be
// used again for a continuous decision.
#include <cstdint>
#include <span>
#include <vector>

namespace volguide {

class DiscreteDistribution {
public:
    DiscreteDistribution() = default;
    // Weights must be finite and >= 0 with a positive sum (throws std::invalid_argument otherwise).
    explicit DiscreteDistribution(std::span<const float> weights);
    size_t size() const { return pmf_.size(); }
    bool empty() const { return pmf_.empty(); }
    double sum() const { return sum_; }
    float pmf(size_t i) const { return pmf_[i]; }
    size_t sample(float u) const;
    // Index plus u rescaled to [0,1) within the chosen entry.
    size_t sample_reuse(float& u) const;

private:
    std::vector<float> pmf_;
    std::vector<double> cdf_;  // cdf_[i] = P(index < i+1); cdf_.back() == 1
    double sum_ = 0.0;
};

}  // namespace volguide
