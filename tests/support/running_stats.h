#pragma once
// Mean and standard error of i.i.d. estimates, for z-tests of unbiased estimators.
#include <cmath>
#include <algorithm>
#include <cstdint>

#include "volguide/core/color.h"

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

// Per channel: the mean and standard error of colour estimates (the error from the population
// variance over n, as the emitter tests' z-tests use it).
struct ColorStats {
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    uint64_t n = 0;
    void add(const Color3& c) {
        for (int i = 0; i < 3; ++i) sum[i] += c[i], sum2[i] += double(c[i]) * c[i];
        ++n;
    }
    double mean(int i) const { return sum[i] / double(n); }
    double se(int i) const {
        const double m = mean(i);
        return std::sqrt(std::max(0.0, sum2[i] / double(n) - m * m) / double(n));
    }
};

}  // namespace volguide::test
