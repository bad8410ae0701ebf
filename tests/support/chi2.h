#pragma once
// Pearson chi-square goodness-of-fit test for sampling routines (oracles.md §8, in the spirit of
// Mitsuba 3's ChiSquareTest).
//
// A sampler is checked against its own pdf: N samples are histogrammed on a grid over the
// sample domain, the pdf is integrated over every cell with adaptive Gauss-Legendre quadrature,
// cells with an expected count below `min_expected` are pooled, and Pearson's statistic is
// compared with the chi-square distribution. Any sample landing in a cell whose integrated pdf is
// exactly zero fails the test. With an `eval` function, every non-delta sample's weight must also
// equal eval / pdf.
//
// Probability mass the pdf does not cover (discrete lobes, failed samples, directions outside a
// zoomed cap) is one extra "rest" bin: expected N * (1 - integral of the pdf over the grid),
// observed = delta samples + invalid ones + those outside the grid.
//
// Usage:
//   ChiSquareOptions opt;
//   opt.test_count = 12;  // number of tests in the family, for the Sidak correction
//   auto r = chi2_test_sphere(
//       [&](Sampler& s) { Vec3f d = ...; return ChiSquareSample{d, weight}; },
//       [&](const Vec3f& d) { return double(pdf(d)); }, opt, eval_fn /* optional */);
//   EXPECT_TRUE(r.passed) << r.report;
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/core/sampler.h"
#include "volguide/core/vec.h"

namespace volguide::test {

struct ChiSquareSample {
    Vec3f d;             // unit direction (sphere) or point with (x, y) used (plane)
    Color3 weight{1.f};  // sample weight, checked against eval / pdf when eval is given
    bool valid = true;   // false: the sampler failed (counts towards the rest bin)
    bool delta = false;  // true: a discrete lobe (counts towards the rest bin, weight not checked)
};

struct ChiSquareOptions {
    uint64_t sample_count = 1000000;
    int rows = 40;  // sphere: bins in cos(theta) over [-1, 1]; plane: bins in y
    int cols = 80;  // sphere: bins in phi over [-pi, pi]; plane: bins in x
    // Sphere only: the grid covers cos(theta) in [min_cos_theta, 1]; samples below count towards
    // the rest bin. Zooms in on a narrow lobe around +z (rotate the lobe there first).
    double min_cos_theta = -1.0;
    double min_expected = 5.0;
    double alpha = 0.01;  // significance level of the whole family of tests
    int test_count = 1;   // Sidak correction: alpha' = 1 - (1 - alpha)^(1 / test_count)
    uint64_t seed = 1;
    // Adaptive quadrature per cell: refine while two estimates differ by more than this
    // (relative to the cell's integral) plus abs_tolerance / sample_count.
    double rel_tolerance = 1e-4;
    double abs_tolerance = 1e-2;
    int max_depth = 6;
    // Weight check: relative tolerance and how many samples to check (0 = none).
    double weight_rel_tolerance = 2e-3;
    uint64_t weight_check_count = 200000;
};

struct ChiSquareResult {
    bool passed = false;
    double statistic = 0.0;
    int dof = 0;
    double p_value = 0.0;
    double alpha_corrected = 0.0;
    double pdf_integral = 0.0;   // quadrature of the pdf over the whole domain
    uint64_t rest_observed = 0;  // delta + invalid samples
    uint64_t zero_pdf_hits = 0;  // samples in cells with zero integrated pdf
    uint64_t weight_mismatches = 0;
    std::string report;  // human-readable summary (always filled)
};

using ChiSquareSampleFn = std::function<ChiSquareSample(Sampler&)>;
using ChiSquarePdfFn = std::function<double(const Vec3f&)>;
using ChiSquareEvalFn = std::function<Color3(const Vec3f&)>;

// Directions on the unit sphere, binned on (cos theta, phi); the pdf is per unit solid angle.
ChiSquareResult chi2_test_sphere(const ChiSquareSampleFn& sample, const ChiSquarePdfFn& pdf,
                                 const ChiSquareOptions& opt = {}, const ChiSquareEvalFn& eval = {});

// Points (d.x, d.y) in the rectangle [x0, x1] x [y0, y1]; the pdf is per unit area.
struct Rect2 {
    double x0 = 0, y0 = 0, x1 = 1, y1 = 1;
};
ChiSquareResult chi2_test_plane(const ChiSquareSampleFn& sample, const ChiSquarePdfFn& pdf, Rect2 domain,
                                const ChiSquareOptions& opt = {}, const ChiSquareEvalFn& eval = {});

// Discrete outcomes: observed counts against expected probabilities (which should sum to 1).
ChiSquareResult chi2_test_discrete(const std::vector<uint64_t>& observed,
                                   const std::vector<double>& probabilities,
                                   const ChiSquareOptions& opt = {});

// Regularized upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a).
double gamma_q(double a, double x);
// P(X >= statistic) for X ~ chi-square with `dof` degrees of freedom.
double chi2_survival(double statistic, int dof);

}  // namespace volguide::test
