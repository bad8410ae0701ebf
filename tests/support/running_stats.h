#pragma once
// Mean and standard error of i.i.d. estimates, for z-tests of unbiased estimators.
#include <cmath>
#include <cstdint>

namespace volguide::test {

struct RunningStats {
    double sum = 0.0, sum2 = 0.0;
    uint64_t n = 0;
    void add(double x) {
        sum += x;
        sum2 += x * x;
        ++n;
    }
    double mean() const { return n ? sum / double(n) : 0.0; }
    double variance() const { return n > 1 ? std::max(0.0, (sum2 - sum * sum / double(n)) / double(n - 1)) : 0.0; }
    double std_error() const { return n ? std::sqrt(variance() / double(n)) : 0.0; }
    // |mean - expected| in standard errors (a floor keeps zero-variance estimators testable).
    double z(double expected, double floor = 1e-12) const {
        return std::abs(mean() - expected) / std::max(std_error(), floor);
    }
};

}  // namespace volguide::test
