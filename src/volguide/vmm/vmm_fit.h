#pragma once
// Weighted EM for a von Mises-Fisher mixture with MAP priors (docs/theory.md §5.4), its stepwise/online
// variant on sufficient statistics (§5.5), and an optional split/merge pass (openpgl-notes §1.4).
//
// Everything is sequential over the samples in their given order, so a fit is a pure function of
// (initial mixture, samples, settings): the same input order gives bit-identical lobes. Statistics
// and likelihoods are accumulated in double; the mixture itself stores floats.
#include <span>

#include "volguide/vmm/vmm.h"

namespace volguide {

// A direction (towards the light, docs/theory.md §1.1) with a non-negative weight (radiance / pdf).
struct DirectionalSample {
    Vec3f direction;
    float weight = 1.f;
};

enum class VmmInit {
    // Weighted k-means++ seeding on the samples (deterministic: a counter-based hash of
    // init_seed drives the choices). Robust against lobes that start between two clusters.
    kmeanspp,
    // Spherical Fibonacci lattice (Open PGL's initialisation; docs/theory.md §5.4).
    fibonacci,
};

struct VmmFitSettings {
    int initial_lobes = 8;  // K of the initialisation (when fit_vmm gets an empty mixture)
    float initial_kappa = 5.f;
    VmmInit init = VmmInit::kmeanspp;
    uint64_t init_seed = 0x766d6d;
    // Independent k-means++ initialisations (seeds init_seed + r); the fit with the highest
    // log-likelihood wins. Guards against the local optima of EM (two lobes on one cluster).
    int restarts = 1;
    int max_iterations = 100;
    double convergence = 0.0025;  // relative change of the weighted log-likelihood (|L| floored at N)
    // MAP priors (docs/theory.md §5.4 defaults): Dirichlet weight prior a; mean-cosine prior r0 with
    // strength b (pulls poorly supported lobes towards broad ones); kappa cap.
    double weight_prior = 0.1;
    double mean_cosine_prior = 0.0;
    double mean_cosine_prior_strength = 0.1;
    float max_kappa = kVmfMaxKappa;
    double min_mixture_pdf = 1e-16;  // samples the mixture cannot explain are skipped in the E-step

    // Split/merge (off by default, see vmm_split_merge.h). A lobe splits when a two-lobe refit of
    // its samples gains more log-likelihood than split_threshold x the BIC penalty; two lobes merge
    // when the relative L2 distance between them and their moment-matched merge is below
    // merge_threshold. Lobe counts stay within [min_lobes, kVmmMaxLobes].
    bool split_and_merge = false;
    double split_threshold = 1.0;
    double merge_threshold = 0.025;
    double min_split_weight = 0.02;  // lobes lighter than this never split
    int min_lobes = 1;
    int max_split_merge_rounds = 4;
};

// Per-lobe sufficient statistics of the weighted E-step: sum u gamma_k and sum u gamma_k w,
// with the weights u normalised so that a batch sums to its sample count (docs/theory.md §5.4).
struct VmmStatistics {
    int count = 0;
    std::array<double, kVmmMaxLobes> weight{};
    std::array<Vec3d, kVmmMaxLobes> direction{};
    double total = 0.0;  // sum of the normalised weights that entered the statistics
    // Evidence the MAP priors are weighed against (N of docs/theory.md §5.4). 0 means `total`. The
    // stepwise fitter's statistics are batch averages, so it sets this to all samples seen.
    double sample_count = 0.0;

    void scale(double s);
    void add_scaled(const VmmStatistics& o, double s);  // this += s * o (same lobe count)
};

struct VmmFitReport {
    int iterations = 0;
    double log_likelihood = 0.0;  // sum of normalised weights * log pdf, after the last E-step
    bool converged = false;
    int splits = 0, merges = 0;
};

// K lobes on a spherical Fibonacci lattice, equal weights, the given kappa.
Vmm fibonacci_vmm(int lobes, float kappa);

// K lobes on sample directions chosen by weighted k-means++ (probability ~ weight x (1 - cos) to
// the nearest chosen axis), equal weights, the given kappa. Falls back to fibonacci_vmm when the
// samples have no positive weight.
Vmm kmeanspp_vmm(std::span<const DirectionalSample> samples, int lobes, float kappa, uint64_t seed);
// The initial mixture the settings ask for.
Vmm initial_vmm(std::span<const DirectionalSample> samples, const VmmFitSettings& settings);

// E-step: statistics of `samples` under `vmm`; returns the weighted log-likelihood.
double expectation(const Vmm& vmm, std::span<const DirectionalSample> samples, const VmmFitSettings& settings,
                   VmmStatistics& stats);
// M-step with the MAP priors; N of docs/theory.md §5.4 is stats.sample_count (or stats.total).
void maximization(Vmm& vmm, const VmmStatistics& stats, const VmmFitSettings& settings);

// Batch EM. Starts from `vmm` if it has lobes (restarts then ignored), from initial_vmm otherwise.
VmmFitReport fit_vmm(Vmm& vmm, std::span<const DirectionalSample> samples,
                     const VmmFitSettings& settings = {});

// Stepwise (online) EM, Cappe & Moulines 2009: per batch t the statistics become
// S = (1 - eta_t) S + eta_t S_t with eta_t = t^-beta, and the mixture is re-maximised. Inside a
// batch the E-step is repeated (against the blended statistics) until the batch likelihood
// converges or inner_iterations is reached. beta = 1 weights all batches equally. The priors are
// weighed against the number of samples seen so far (no forgetting, as in Open PGL), so they
// weaken as evidence accumulates exactly as in a batch fit of the same samples.
class StepwiseVmmFitter {
  public:
    explicit StepwiseVmmFitter(const VmmFitSettings& settings = {}, double beta = 0.7,
                               int inner_iterations = 20);
    // Continue from an existing mixture (e.g. a parent leaf's); its statistics start empty.
    void reset(const Vmm& vmm);
    VmmFitReport add_batch(std::span<const DirectionalSample> samples);

    const Vmm& vmm() const { return vmm_; }
    const VmmStatistics& statistics() const { return stats_; }
    int batches() const { return batches_; }

  private:
    VmmFitSettings settings_;
    double beta_;
    int inner_iterations_;
    Vmm vmm_;
    VmmStatistics stats_;
    int batches_ = 0;
    double samples_seen_ = 0.0;  // prior reference: all (normalised) samples so far
};

}  // namespace volguide
