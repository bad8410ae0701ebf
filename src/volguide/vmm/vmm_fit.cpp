#include "volguide/vmm/vmm_fit.h"

#include <cmath>
#include <limits>
#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/vmm/vmm_split_merge.h"

namespace volguide {

void VmmStatistics::scale(double s) {
    for (int k = 0; k < count; ++k) {
        weight[k] *= s;
        direction[k] *= s;
    }
    total *= s;
}

void VmmStatistics::add_scaled(const VmmStatistics& o, double s) {
    for (int k = 0; k < count; ++k) {
        weight[k] += s * o.weight[k];
        direction[k] += o.direction[k] * s;
    }
    total += s * o.total;
}

Vmm fibonacci_vmm(int lobes, float kappa) {
    Vmm m;
    lobes = std::clamp(lobes, 1, kVmmMaxLobes);
    const double golden = (1.0 + std::sqrt(5.0)) / 2.0;
    for (int i = 0; i < lobes; ++i) {
        double z = 1.0 - (2.0 * i + 1.0) / lobes;
        double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        double phi = 2.0 * M_PI * std::fmod(i / golden, 1.0);
        m.add_lobe(1.f / float(lobes),
                   VmfLobe(Vec3f(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)), kappa));
    }
    return m;
}

Vmm kmeanspp_vmm(std::span<const DirectionalSample> samples, int lobes, float kappa, uint64_t seed) {
    lobes = std::clamp(lobes, 1, kVmmMaxLobes);
    auto usable = [](const DirectionalSample& s) { return s.weight > 0.f && std::isfinite(s.weight); };
    // distance[i] = weight x (1 - cos) to the nearest chosen axis (initially: the weight alone).
    std::vector<double> distance(samples.size()), trial(samples.size()), best(samples.size());
    double total = 0.0;
    for (size_t i = 0; i < samples.size(); ++i)
        total += distance[i] = usable(samples[i]) ? samples[i].weight : 0.0;
    if (!(total > 0.0)) return fibonacci_vmm(lobes, kappa);
    // Greedy k-means++ (Arthur & Vassilvitskii 2007): of 2 + ln K candidates drawn ~ distance, keep
    // the one that lowers the total distance most; far more robust than a single draw.
    const int candidates = 2 + int(std::log(double(lobes)));
    Vmm m;
    for (int k = 0; k < lobes; ++k) {
        if (!(total > 0.0)) break;  // every sample sits on a chosen axis
        double best_total = std::numeric_limits<double>::infinity();
        Vec3f best_mu;
        for (int c = 0; c < (k == 0 ? 1 : candidates); ++c) {
            Sampler rng(seed, uint64_t(k), uint64_t(c));
            double target = double(rng.next_1d()) * total;
            size_t pick = 0;
            for (size_t i = 0; i < samples.size(); ++i) {
                if (distance[i] <= 0.0) continue;
                pick = i;
                if ((target -= distance[i]) < 0.0) break;
            }
            Vec3f mu = normalize(samples[pick].direction);
            double t = 0.0;
            for (size_t i = 0; i < samples.size(); ++i) {
                if (!usable(samples[i])) {
                    trial[i] = 0.0;
                    continue;
                }
                double d = double(samples[i].weight) * one_minus_cos(samples[i].direction, mu);
                trial[i] = k == 0 ? d : std::min(distance[i], d);
                t += trial[i];
            }
            if (t < best_total) {
                best_total = t;
                best_mu = mu;
                best.swap(trial);
            }
        }
        m.add_lobe(1.f, VmfLobe(best_mu, kappa));
        distance.swap(best);
        total = best_total;
    }
    m.normalize_weights();
    return m;
}

Vmm initial_vmm(std::span<const DirectionalSample> samples, const VmmFitSettings& settings) {
    if (settings.init == VmmInit::fibonacci)
        return fibonacci_vmm(settings.initial_lobes, settings.initial_kappa);
    return kmeanspp_vmm(samples, settings.initial_lobes, settings.initial_kappa, settings.init_seed);
}

double expectation(const Vmm& vmm, std::span<const DirectionalSample> samples, const VmmFitSettings& settings,
                   VmmStatistics& stats) {
    stats = VmmStatistics{};
    stats.count = vmm.count;
    double weight_sum = 0.0;
    for (const DirectionalSample& s : samples)
        if (s.weight > 0.f && std::isfinite(s.weight)) weight_sum += s.weight;
    if (!(weight_sum > 0.0) || vmm.count == 0) return 0.0;
    // Normalised weights sum to the sample count, so statistics scale with evidence, not radiance.
    const double normaliser = double(samples.size()) / weight_sum;

    double log_likelihood = 0.0;
    std::array<float, kVmmMaxLobes> v{};
    for (const DirectionalSample& s : samples) {
        if (!(s.weight > 0.f) || !std::isfinite(s.weight)) continue;
        const Vec3f& w = s.direction;
        float pdf = 0.f;
        for (int k = 0; k < vmm.count; ++k) {
            float dx = w.x - vmm.mu_x[k], dy = w.y - vmm.mu_y[k], dz = w.z - vmm.mu_z[k];
            float one_minus = std::min(0.5f * (dx * dx + dy * dy + dz * dz), 2.f);
            v[k] = vmm.weight[k] * vmm.norm[k] * std::exp(-vmm.kappa[k] * one_minus);
            pdf += v[k];
        }
        if (!(pdf > settings.min_mixture_pdf)) continue;
        double u = s.weight * normaliser;
        log_likelihood += u * std::log(double(pdf));
        double scale = u / pdf;
        Vec3d wd(w);
        for (int k = 0; k < vmm.count; ++k) {
            double g = v[k] * scale;
            stats.weight[k] += g;
            stats.direction[k] += wd * g;
        }
        stats.total += u;
    }
    return log_likelihood;
}

void maximization(Vmm& vmm, const VmmStatistics& stats, const VmmFitSettings& settings) {
    const int K = stats.count;
    if (!(stats.total > 0.0)) return;
    // Statistics in units of the evidence N the priors are weighed against.
    const double N = stats.sample_count > 0.0 ? stats.sample_count : stats.total;
    const double to_samples = N / stats.total;
    const double a = settings.weight_prior, b = settings.mean_cosine_prior_strength,
                 r0 = settings.mean_cosine_prior;
    const double r_max = vmf_mean_cosine(settings.max_kappa);
    for (int k = 0; k < K; ++k) {
        double n_k = stats.weight[k];
        double pi = (n_k * to_samples + a) / (N + K * a);
        double length = norm(stats.direction[k]);
        Vec3f mu = length > 0.0 ? Vec3f(stats.direction[k] / length) : vmm.lobe(k).mu;
        double r = n_k > 0.0 ? std::min(length / n_k, 1.0) : 0.0;
        double n_prior = pi * N;
        double r_map = (r0 * b + r * n_prior) / (b + n_prior);
        double kappa = vmf_kappa_from_mean_cosine(std::min(r_map, r_max), settings.max_kappa);
        vmm.set_lobe(k, float(pi), VmfLobe(mu, float(kappa)));
    }
    vmm.normalize_weights();
}

namespace {
// Relative change of the log-likelihood, with |L| floored at the sample count N: a likelihood
// near 0 (mixture pdf ~ 1 on average) would otherwise never count as converged.
bool converged(double previous, double current, double tolerance, double sample_count) {
    return std::abs(current - previous) <= tolerance * std::max({std::abs(previous), sample_count, 1e-300});
}

VmmFitReport run_em(Vmm& vmm, std::span<const DirectionalSample> samples, const VmmFitSettings& settings) {
    VmmFitReport report;
    VmmStatistics stats;
    double previous = 0.0;
    for (int it = 0; it < settings.max_iterations; ++it) {
        double ll = expectation(vmm, samples, settings, stats);
        maximization(vmm, stats, settings);
        report.iterations = it + 1;
        report.log_likelihood = ll;
        if (it > 0 && converged(previous, ll, settings.convergence, stats.total)) {
            report.converged = true;
            break;
        }
        previous = ll;
    }
    return report;
}
}  // namespace

namespace {
VmmFitReport fit_from(Vmm& vmm, std::span<const DirectionalSample> samples, const VmmFitSettings& settings) {
    VmmFitReport report = run_em(vmm, samples, settings);
    if (!settings.split_and_merge) return report;
    for (int round = 0; round < settings.max_split_merge_rounds; ++round) {
        int splits = split_lobes(vmm, samples, settings);
        if (splits > 0) run_em(vmm, samples, settings);
        int merges = merge_redundant_lobes(vmm, settings);
        if (merges > 0) run_em(vmm, samples, settings);
        report.splits += splits;
        report.merges += merges;
        if (splits == 0 && merges == 0) break;
    }
    VmmFitReport last = run_em(vmm, samples, settings);
    last.splits = report.splits;
    last.merges = report.merges;
    last.iterations += report.iterations;
    return last;
}
}  // namespace

VmmFitReport fit_vmm(Vmm& vmm, std::span<const DirectionalSample> samples, const VmmFitSettings& settings) {
    if (vmm.count > 0) return fit_from(vmm, samples, settings);
    VmmFitReport best_report;
    Vmm best;
    VmmFitSettings s = settings;
    for (int r = 0; r < std::max(settings.restarts, 1); ++r) {
        if (settings.init == VmmInit::fibonacci && r > 0) break;  // deterministic lattice: one start
        s.init_seed = settings.init_seed + uint64_t(r);
        Vmm candidate = initial_vmm(samples, s);
        VmmFitReport report = fit_from(candidate, samples, s);
        if (r == 0 || report.log_likelihood > best_report.log_likelihood) {
            best_report = report;
            best = candidate;
        }
    }
    vmm = best;
    return best_report;
}

StepwiseVmmFitter::StepwiseVmmFitter(const VmmFitSettings& settings, double beta, int inner_iterations)
    : settings_(settings), beta_(beta), inner_iterations_(std::max(inner_iterations, 1)) {}

void StepwiseVmmFitter::reset(const Vmm& vmm) {
    vmm_ = vmm;
    stats_ = VmmStatistics{};
    batches_ = 0;
    samples_seen_ = 0.0;
}

VmmFitReport StepwiseVmmFitter::add_batch(std::span<const DirectionalSample> samples) {
    if (vmm_.count == 0) vmm_ = initial_vmm(samples, settings_);
    ++batches_;
    const double eta = batches_ == 1 ? 1.0 : std::pow(double(batches_), -beta_);
    const VmmStatistics previous = stats_;
    VmmFitReport report;
    VmmStatistics batch, blended;
    double previous_ll = 0.0;
    for (int it = 0; it < inner_iterations_; ++it) {
        double ll = expectation(vmm_, samples, settings_, batch);
        blended = batch;
        blended.scale(eta);
        if (eta < 1.0) blended.add_scaled(previous, 1.0 - eta);
        blended.sample_count = samples_seen_ + batch.total;
        maximization(vmm_, blended, settings_);
        report.iterations = it + 1;
        report.log_likelihood = ll;
        if (it > 0 && converged(previous_ll, ll, settings_.convergence, batch.total)) {
            report.converged = true;
            break;
        }
        previous_ll = ll;
    }
    stats_ = blended;
    samples_seen_ = blended.sample_count;
    return report;
}

}  // namespace volguide
