#include "support/chi2.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace volguide::test {

// ---------------------------------------------------------------------------------------------
// Chi-square distribution

double gamma_q(double a, double x) {
    if (x <= 0.0) return 1.0;
    const double log_prefix = a * std::log(x) - x - std::lgamma(a);
    if (x < a + 1.0) {
        // Series for P(a, x); Q = 1 - P.
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 100000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-15) break;
        }
        return std::max(0.0, 1.0 - sum * std::exp(log_prefix));
    }
    // Continued fraction for Q(a, x) (modified Lentz).
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-15) break;
    }
    return std::exp(log_prefix) * h;
}

double chi2_survival(double statistic, int dof) {
    if (dof <= 0) return 1.0;
    return gamma_q(0.5 * dof, 0.5 * statistic);
}

namespace {

double sidak_alpha(const ChiSquareOptions& opt) {
    return 1.0 - std::pow(1.0 - opt.alpha, 1.0 / std::max(1, opt.test_count));
}

// Pools small bins, computes Pearson's statistic and fills the verdict fields of `r`.
// `label(i)` names bin i in the report.
void pearson(const std::vector<double>& obs, const std::vector<double>& expct, const ChiSquareOptions& opt,
             const std::function<std::string(size_t)>& label, ChiSquareResult& r) {
    struct Bin {
        double o, e;
        size_t index;  // SIZE_MAX for the pooled bin
    };
    std::vector<Bin> bins;
    Bin pooled{0.0, 0.0, SIZE_MAX};
    for (size_t i = 0; i < obs.size(); ++i) {
        if (expct[i] < opt.min_expected) {
            pooled.o += obs[i];
            pooled.e += expct[i];
        } else {
            bins.push_back({obs[i], expct[i], i});
        }
    }
    if (pooled.e > 0.0 || pooled.o > 0.0) {
        if (pooled.e < opt.min_expected && !bins.empty()) {
            // Still too small: merge into the smallest regular bin.
            auto smallest = std::min_element(bins.begin(), bins.end(),
                                             [](const Bin& a, const Bin& b) { return a.e < b.e; });
            smallest->o += pooled.o;
            smallest->e += pooled.e;
        } else {
            bins.push_back(pooled);
        }
    }
    r.statistic = 0.0;
    for (const Bin& b : bins) r.statistic += b.e > 0.0 ? sqr(b.o - b.e) / b.e : (b.o > 0.0 ? INFINITY : 0.0);
    r.dof = int(bins.size()) - 1;
    r.alpha_corrected = sidak_alpha(opt);
    r.p_value = std::isfinite(r.statistic) ? chi2_survival(r.statistic, r.dof) : 0.0;
    bool ok = r.dof > 0 && r.p_value >= r.alpha_corrected && r.zero_pdf_hits == 0 && r.weight_mismatches == 0;
    r.passed = ok;

    std::string& s = r.report;
    s += fmt::format(
        "chi-square test {}: statistic {:.2f}, dof {}, p-value {:.4g} (alpha' = {:.4g}: alpha {} over {} "
        "tests)\n",
        ok ? "passed" : "FAILED", r.statistic, r.dof, r.p_value, r.alpha_corrected, opt.alpha,
        opt.test_count);
    if (r.dof <= 0) s += "  too few bins with enough expected samples for a test\n";
    // The bins contributing most to the statistic, to locate a disagreement.
    std::vector<size_t> order(bins.size());
    std::iota(order.begin(), order.end(), 0);
    auto contrib = [&](size_t i) {
        return bins[i].e > 0.0 ? sqr(bins[i].o - bins[i].e) / bins[i].e : INFINITY;
    };
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return contrib(a) > contrib(b); });
    s += "  largest contributions (observed vs expected):\n";
    for (size_t k = 0; k < std::min<size_t>(6, order.size()); ++k) {
        const Bin& b = bins[order[k]];
        s += fmt::format("    {}: {:.0f} vs {:.1f} ({:+.1f} sigma)\n",
                         b.index == SIZE_MAX ? std::string("pooled small cells") : label(b.index), b.o, b.e,
                         b.e > 0.0 ? (b.o - b.e) / std::sqrt(b.e) : INFINITY);
    }
}

// A 2-D parameter domain [x0, x1] x [y0, y1] mapped to the sampler's space.
struct Domain {
    Rect2 r;
    bool sphere = false;  // x = phi, y = cos(theta)
    Vec3f point(double x, double y) const {
        if (!sphere) return Vec3f(float(x), float(y), 0.f);
        double st = std::sqrt(std::max(0.0, 1.0 - y * y));
        return Vec3f(float(st * std::cos(x)), float(st * std::sin(x)), float(y));
    }
    // Quadrature runs in (phi, theta) on the sphere, with the Jacobian sin(theta): peaks at the
    // poles are far narrower in cos(theta) than in theta and would be missed.
    double quad_y(double y) const { return sphere ? std::acos(std::clamp(y, -1.0, 1.0)) : y; }
    double integrand(const ChiSquarePdfFn& pdf, double x, double t) const {
        if (!sphere) return pdf(point(x, t));
        return pdf(point(x, std::cos(t))) * std::sin(t);
    }
    // Parameter coordinates of a sample.
    Vec2<double> coords(const Vec3f& d) const {
        if (!sphere) return {double(d.x), double(d.y)};
        return {std::atan2(double(d.y), double(d.x)), std::clamp(double(d.z), -1.0, 1.0)};
    }
};

// 5-point Gauss-Legendre on [-1, 1].
constexpr double kNodes[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                              0.9061798459386640};
constexpr double kWeights[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                0.4786286704993665, 0.2369268850561891};

struct Integrator {
    const Domain& dom;
    const ChiSquarePdfFn& pdf;
    double abs_tol, rel_tol;
    int max_depth;

    double gauss(double x0, double x1, double y0, double y1) const {
        double hx = 0.5 * (x1 - x0), hy = 0.5 * (y1 - y0), cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
        double sum = 0.0;
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i) {
                double v = dom.integrand(pdf, cx + hx * kNodes[i], cy + hy * kNodes[j]);
                sum += kWeights[i] * kWeights[j] * v;
            }
        return sum * hx * hy;
    }
    double adaptive(double x0, double x1, double y0, double y1, double whole, int depth) const {
        double xm = 0.5 * (x0 + x1), ym = 0.5 * (y0 + y1);
        double q[4] = {gauss(x0, xm, y0, ym), gauss(xm, x1, y0, ym), gauss(x0, xm, ym, y1),
                       gauss(xm, x1, ym, y1)};
        double refined = q[0] + q[1] + q[2] + q[3];
        if (depth >= max_depth || std::abs(refined - whole) <= rel_tol * std::abs(refined) + abs_tol)
            return refined;
        return adaptive(x0, xm, y0, ym, q[0], depth + 1) + adaptive(xm, x1, y0, ym, q[1], depth + 1) +
               adaptive(x0, xm, ym, y1, q[2], depth + 1) + adaptive(xm, x1, ym, y1, q[3], depth + 1);
    }
    double cell(double x0, double x1, double y0, double y1) const {
        return adaptive(x0, x1, y0, y1, gauss(x0, x1, y0, y1), 0);
    }
};

ChiSquareResult run(const ChiSquareSampleFn& sample, const ChiSquarePdfFn& pdf, const Domain& dom,
                    const ChiSquareOptions& opt, const ChiSquareEvalFn& eval) {
    ChiSquareResult r;
    const int rows = opt.rows, cols = opt.cols;
    const double dx = (dom.r.x1 - dom.r.x0) / cols, dy = (dom.r.y1 - dom.r.y0) / rows;
    std::vector<double> obs(size_t(rows) * cols + 1, 0.0);  // last entry: the rest bin
    uint64_t bad = 0, outside = 0, weights_checked = 0;
    std::string first_problems;

    for (uint64_t i = 0; i < opt.sample_count; ++i) {
        Sampler sampler(opt.seed, 0, i, 0xC412);
        ChiSquareSample s = sample(sampler);
        if (!s.valid || s.delta) {
            ++r.rest_observed;
            continue;
        }
        bool finite = all_finite(s.d) && s.weight.is_finite();
        if (!finite || (dom.sphere && std::abs(squared_norm(s.d) - 1.f) > 1e-3f)) {
            if (bad++ < 3)
                first_problems += fmt::format("  bad sample #{}: d = ({}, {}, {}), weight = ({}, {}, {})\n",
                                              i, s.d.x, s.d.y, s.d.z, s.weight.r, s.weight.g, s.weight.b);
            continue;
        }
        Vec2<double> c = dom.coords(s.d);
        if (dom.sphere && c.y < dom.r.y0) {
            ++r.rest_observed;  // outside a zoomed cap (min_cos_theta)
            continue;
        }
        int col = int(std::floor((c.x - dom.r.x0) / dx)), row = int(std::floor((c.y - dom.r.y0) / dy));
        if (dom.sphere) {
            col = std::clamp(col, 0, cols - 1);
            row = std::clamp(row, 0, rows - 1);
        } else if (col < 0 || col >= cols || row < 0 || row >= rows) {
            if (outside++ < 3)
                first_problems += fmt::format("  sample #{} outside the domain: ({}, {})\n", i, c.x, c.y);
            continue;
        }
        obs[size_t(row) * cols + col] += 1.0;

        if (eval && weights_checked < opt.weight_check_count) {
            ++weights_checked;
            double p = pdf(s.d);
            Color3 f = eval(s.d);
            for (int k = 0; k < 3; ++k) {
                double expected = p > 0.0 ? f[k] / p : 0.0;
                double tol =
                    opt.weight_rel_tolerance * std::max(std::abs(expected), double(std::abs(s.weight[k]))) +
                    1e-6;
                if (!(std::abs(s.weight[k] - expected) <= tol)) {
                    if (r.weight_mismatches++ < 3)
                        first_problems += fmt::format(
                            "  weight mismatch #{}: d = ({:.5f}, {:.5f}, {:.5f}), weight[{}] = {:.6g}, "
                            "eval/pdf = {:.6g}/{:.6g} = {:.6g}\n",
                            i, s.d.x, s.d.y, s.d.z, k, s.weight[k], f[k], p, expected);
                    break;
                }
            }
        }
    }

    // Expected counts per cell.
    const double n = double(opt.sample_count);
    Integrator integ{dom, pdf, opt.abs_tolerance / n, opt.rel_tolerance, opt.max_depth};
    std::vector<double> expct(obs.size(), 0.0);
    double total = 0.0;
    for (int row = 0; row < rows; ++row)
        for (int col = 0; col < cols; ++col) {
            double x0 = dom.r.x0 + col * dx, y0 = dom.r.y0 + row * dy;
            // In theta, the cell [y0, y0 + dy] of cos(theta) is [acos(y0 + dy), acos(y0)].
            double t0 = dom.quad_y(y0), t1 = dom.quad_y(y0 + dy);
            double m = std::abs(integ.cell(x0, x0 + dx, std::min(t0, t1), std::max(t0, t1)));
            size_t idx = size_t(row) * cols + col;
            expct[idx] = m * n;
            total += m;
            if (m == 0.0 && obs[idx] > 0.0) {
                if (r.zero_pdf_hits == 0)
                    first_problems += fmt::format(
                        "  {} samples in a cell with zero pdf: x [{:.4f}, {:.4f}], y [{:.4f}, {:.4f}]\n",
                        obs[idx], x0, x0 + dx, y0, y0 + dy);
                r.zero_pdf_hits += uint64_t(obs[idx]);
            }
        }
    r.pdf_integral = total;
    obs.back() = double(r.rest_observed);
    expct.back() = std::max(0.0, 1.0 - total) * n;

    r.report = fmt::format(
        "  {} samples, pdf integral {:.6f}, rest bin (delta/invalid/outside) observed {} expected {:.1f}\n",
        opt.sample_count, total, r.rest_observed, expct.back());
    if (r.zero_pdf_hits) r.report += fmt::format("  {} samples in zero-pdf cells\n", r.zero_pdf_hits);
    if (r.weight_mismatches)
        r.report += fmt::format("  {} of {} checked weights differ from eval/pdf\n", r.weight_mismatches,
                                weights_checked);
    if (bad) r.report += fmt::format("  {} non-finite or non-unit samples\n", bad);
    if (outside) r.report += fmt::format("  {} samples outside the domain\n", outside);
    r.report += first_problems;

    auto label = [&](size_t idx) {
        if (idx == obs.size() - 1) return std::string("rest bin (delta/invalid/outside)");
        int row = int(idx / cols), col = int(idx % cols);
        double x0 = dom.r.x0 + col * dx, y0 = dom.r.y0 + row * dy;
        return dom.sphere
                   ? fmt::format("cos_theta [{:.3f}, {:.3f}] phi [{:.3f}, {:.3f}]", y0, y0 + dy, x0, x0 + dx)
                   : fmt::format("x [{:.4g}, {:.4g}] y [{:.4g}, {:.4g}]", x0, x0 + dx, y0, y0 + dy);
    };
    std::string details = std::move(r.report);
    r.report.clear();
    pearson(obs, expct, opt, label, r);
    r.report += details;
    if ((bad || outside) && r.passed) {
        r.passed = false;
        r.report.replace(r.report.find("passed"), 6, "FAILED");
    }
    return r;
}

}  // namespace

ChiSquareResult chi2_test_sphere(const ChiSquareSampleFn& sample, const ChiSquarePdfFn& pdf,
                                 const ChiSquareOptions& opt, const ChiSquareEvalFn& eval) {
    Domain dom{Rect2{-M_PI, std::clamp(opt.min_cos_theta, -1.0, 0.999), M_PI, 1.0}, true};
    return run(sample, pdf, dom, opt, eval);
}

ChiSquareResult chi2_test_plane(const ChiSquareSampleFn& sample, const ChiSquarePdfFn& pdf, Rect2 domain,
                                const ChiSquareOptions& opt, const ChiSquareEvalFn& eval) {
    return run(sample, pdf, Domain{domain, false}, opt, eval);
}

ChiSquareResult chi2_test_discrete(const std::vector<uint64_t>& observed,
                                   const std::vector<double>& probabilities, const ChiSquareOptions& opt) {
    ChiSquareResult r;
    double n = 0.0;
    for (uint64_t o : observed) n += double(o);
    std::vector<double> obs(observed.begin(), observed.end()), expct(probabilities.size());
    for (size_t i = 0; i < expct.size(); ++i) {
        expct[i] = probabilities[i] * n;
        if (probabilities[i] == 0.0 && observed[i] > 0) r.zero_pdf_hits += observed[i];
    }
    pearson(
        obs, expct, opt, [](size_t i) { return fmt::format("outcome {}", i); }, r);
    if (r.zero_pdf_hits)
        r.report += fmt::format("  {} samples in zero-probability outcomes\n", r.zero_pdf_hits);
    return r;
}

}  // namespace volguide::test
