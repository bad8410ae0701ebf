#include "volguide/vmm/phase_vmm_fit.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/vmm/vmf.h"

namespace volguide {

namespace {
constexpr int kMaxParams = 2 * kPhaseVmmMaxLobes - 1;
constexpr double kLogKappaMin = -9.0, kLogKappaMax = 12.0;  // kappa in [1.2e-4, 1.6e5]

// d ln c~(kappa) / d kappa = 1/kappa - 2 e^-2k / (1 - e^-2k); series near 0 (limit 1).
double dlog_norm(double k) {
    if (k < 1e-3) return 1.0 - k / 3.0;
    return 1.0 / k + 2.0 * std::exp(-2.0 * k) / std::expm1(-2.0 * k);
}

std::vector<double> make_grid(double g, const HgFitSettings& s) {
    std::vector<double> cosines;
    for (int n = 0; n < s.grid; ++n) cosines.push_back(std::cos(PiDouble * n / (s.grid - 1)));
    // Above g = 0.95 the peak (~(1 - g) wide) falls between grid angles: add points inside it. Their
    // number ramps up from 0 at g = 0.95 to grid/2 at g = 0.97 so the objective (and the table)
    // stays continuous in g.
    int extra = int(std::lround(std::clamp((g - 0.95) / 0.02, 0.0, 1.0) * (s.grid / 2)));
    double extent = 20.0 * (1.0 - g);
    for (int n = 1; n <= extra; ++n) cosines.push_back(std::cos(extent * n / extra));
    return cosines;
}

// Parameters x: softmax logits a_1..a_{K-1} (a_0 = 0), then log kappa_0..kappa_{K-1}.
struct Model {
    int K;
    std::array<double, kPhaseVmmMaxLobes> w, kappa;
    void set(const double* x) {
        double m = 0.0;
        std::array<double, kPhaseVmmMaxLobes> a{};
        for (int j = 1; j < K; ++j) a[j] = x[j - 1], m = std::max(m, a[j]);
        double sum = 0.0;
        for (int j = 0; j < K; ++j) sum += w[j] = std::exp(a[j] - m);
        for (int j = 0; j < K; ++j) w[j] /= sum, kappa[j] = std::exp(x[K - 1 + j]);
    }
};

struct Problem {
    double g, eps;
    std::vector<double> cosines, target;  // target = ln(f_HG + eps)
    int K;

    double cost(const Model& m) const {
        double c = 0.0;
        std::array<double, kPhaseVmmMaxLobes> scale{};
        for (int j = 0; j < K; ++j) scale[j] = m.w[j] * vmf_normalization(m.kappa[j]);
        for (size_t n = 0; n < cosines.size(); ++n) {
            double v = 0.0;
            for (int j = 0; j < K; ++j) v += scale[j] * std::exp(-m.kappa[j] * (1.0 - cosines[n]));
            double r = target[n] - std::log(v + eps);
            c += r * r;
        }
        return c;
    }
    // Normal equations J^T J and J^T r (J = d residual / d x).
    double linearise(const Model& m, double* jtj, double* jtr) const {
        const int P = 2 * K - 1;
        std::fill(jtj, jtj + P * P, 0.0);
        std::fill(jtr, jtr + P, 0.0);
        double c = 0.0;
        std::array<double, kPhaseVmmMaxLobes> norm{}, dnorm{};
        for (int j = 0; j < K; ++j) norm[j] = vmf_normalization(m.kappa[j]), dnorm[j] = dlog_norm(m.kappa[j]);
        for (size_t n = 0; n < cosines.size(); ++n) {
            double omc = 1.0 - cosines[n];
            std::array<double, kPhaseVmmMaxLobes> v{};
            double mix = 0.0;
            for (int j = 0; j < K; ++j) mix += m.w[j] * (v[j] = norm[j] * std::exp(-m.kappa[j] * omc));
            double r = target[n] - std::log(mix + eps);
            c += r * r;
            double inv = -1.0 / (mix + eps);
            std::array<double, kMaxParams> J{};
            for (int j = 1; j < K; ++j) J[j - 1] = inv * m.w[j] * (v[j] - mix);
            for (int j = 0; j < K; ++j) J[K - 1 + j] = inv * m.w[j] * v[j] * m.kappa[j] * (dnorm[j] - omc);
            for (int p = 0; p < P; ++p) {
                jtr[p] += J[p] * r;
                for (int q = 0; q <= p; ++q) jtj[p * P + q] += J[p] * J[q];
            }
        }
        for (int p = 0; p < P; ++p)
            for (int q = p + 1; q < P; ++q) jtj[p * P + q] = jtj[q * P + p];
        return c;
    }
};

// Solves A x = b (A symmetric positive definite, small) by Cholesky; false if not SPD.
bool solve_spd(int n, double* A, double* b) {
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j <= i; ++j) {
            double s = A[i * n + j];
            for (int k = 0; k < j; ++k) s -= A[i * n + k] * A[j * n + k];
            if (i == j) {
                if (!(s > 0.0)) return false;
                A[i * n + i] = std::sqrt(s);
            } else {
                A[i * n + j] = s / A[j * n + j];
            }
        }
    }
    for (int i = 0; i < n; ++i) {
        for (int k = 0; k < i; ++k) b[i] -= A[i * n + k] * b[k];
        b[i] /= A[i * n + i];
    }
    for (int i = n - 1; i >= 0; --i) {
        for (int k = i + 1; k < n; ++k) b[i] -= A[k * n + i] * b[k];
        b[i] /= A[i * n + i];
    }
    return true;
}

// Levenberg-Marquardt from x; returns the final cost and leaves the optimum in x.
double levenberg_marquardt(const Problem& pr, double* x, int max_iterations) {
    const int P = 2 * pr.K - 1;
    Model m{pr.K, {}, {}};
    m.set(x);
    std::array<double, kMaxParams * kMaxParams> jtj{}, A{};
    std::array<double, kMaxParams> jtr{}, step{}, trial{};
    double cost = pr.linearise(m, jtj.data(), jtr.data());
    double lambda = 1e-3;
    int stalls = 0;
    for (int it = 0; it < max_iterations && stalls < 8; ++it) {
        A = jtj;
        for (int p = 0; p < P; ++p) A[p * P + p] += lambda * std::max(jtj[p * P + p], 1e-12);
        for (int p = 0; p < P; ++p) step[p] = jtr[p];  // J^T r; the step is -(J^T J)^-1 J^T r with J = dr/dx
        if (!solve_spd(P, A.data(), step.data())) {
            lambda *= 10.0;
            continue;
        }
        for (int p = 0; p < P; ++p) trial[p] = x[p] - step[p];
        for (int j = 0; j < pr.K; ++j)
            trial[P - pr.K + j] = std::clamp(trial[P - pr.K + j], kLogKappaMin, kLogKappaMax);
        for (int p = 0; p < pr.K - 1; ++p) trial[p] = std::clamp(trial[p], -30.0, 30.0);
        Model mt{pr.K, {}, {}};
        mt.set(trial.data());
        double c = pr.cost(mt);
        if (c < cost) {
            stalls = (cost - c) < 1e-12 * cost + 1e-20 ? stalls + 1 : 0;
            std::copy(trial.begin(), trial.begin() + P, x);
            m = mt;
            cost = pr.linearise(m, jtj.data(), jtr.data());
            lambda = std::max(lambda / 3.0, 1e-12);
        } else {
            lambda *= 4.0;
            if (lambda > 1e12) break;
        }
    }
    return cost;
}

Problem make_problem(double g, const HgFitSettings& s) {
    Problem pr;
    pr.g = g;
    pr.K = std::clamp(s.lobes, 1, kPhaseVmmMaxLobes);
    pr.eps = s.epsilon * hg_density(g, 1.0);
    pr.cosines = make_grid(g, s);
    for (double c : pr.cosines) pr.target.push_back(std::log(hg_density(g, c) + pr.eps));
    return pr;
}

ZonalFit to_fit(const Problem& pr, const double* x, double cost) {
    Model m{pr.K, {}, {}};
    m.set(x);
    std::array<int, kPhaseVmmMaxLobes> order{0, 1, 2, 3};
    for (int i = 1; i < pr.K; ++i)  // insertion sort by decreasing kappa
        for (int j = i; j > 0 && m.kappa[order[j]] > m.kappa[order[j - 1]]; --j)
            std::swap(order[j], order[j - 1]);
    ZonalFit f;
    f.lobes = pr.K;
    for (int j = 0; j < pr.K; ++j) {
        f.weight[j] = m.w[order[j]];
        f.kappa[j] = m.kappa[order[j]];
        f.mean_cosine += f.weight[j] * vmf_mean_cosine(f.kappa[j]);
    }
    f.rms_log = std::sqrt(cost / pr.cosines.size());
    return f;
}

void from_fit(const ZonalFit& f, int K, double* x) {
    for (int j = 1; j < K; ++j)
        x[j - 1] = std::log(std::max(f.weight[j], 1e-12) / std::max(f.weight[0], 1e-12));
    for (int j = 0; j < K; ++j)
        x[K - 1 + j] = std::clamp(std::log(std::max(f.kappa[j], 1e-6)), kLogKappaMin, kLogKappaMax);
}
}  // namespace

double hg_density(double g, double cos_theta) {
    double denom = 1.0 + g * g - 2.0 * g * cos_theta;
    return (1.0 - g * g) / (4.0 * PiDouble * denom * std::sqrt(denom));
}

ZonalFit fit_hg_zonal(double g, const HgFitSettings& settings, const ZonalFit* warm_start) {
    Problem pr = make_problem(g, settings);
    const int K = pr.K, P = 2 * K - 1;
    double best_cost = std::numeric_limits<double>::infinity();
    std::array<double, kMaxParams> best{}, x{};
    auto consider = [&](double c) {
        if (c < best_cost) best_cost = c, best = x;
    };
    if (warm_start && warm_start->lobes == K) {
        from_fit(*warm_start, K, x.data());
        consider(levenberg_marquardt(pr, x.data(), settings.max_iterations));
    }
    const double kmin = 0.05, kmax = std::max(5.0 / ((1.0 - g) * (1.0 - g)), 0.1);
    for (int s = 0; s < settings.starts; ++s) {
        Sampler rng(settings.seed, uint64_t(std::llround(g * 1e6)), uint64_t(s));
        x.fill(0.0);
        for (int j = 0; j < K; ++j)
            x[K - 1 + j] = std::log(kmin) + rng.next_1d() * (std::log(kmax) - std::log(kmin));
        consider(levenberg_marquardt(pr, x.data(), settings.max_iterations));
    }
    (void)P;
    x = best;
    return to_fit(pr, best.data(), best_cost);
}

double hg_fit_rms_log(double g, const ZonalFit& fit, const HgFitSettings& settings) {
    Problem pr = make_problem(g, settings);
    pr.K = fit.lobes;
    Model m{fit.lobes, {}, {}};
    for (int j = 0; j < fit.lobes; ++j) m.w[j] = fit.weight[j], m.kappa[j] = fit.kappa[j];
    return std::sqrt(pr.cost(m) / pr.cosines.size());
}

}  // namespace volguide
