#pragma once
// Guided product distance sampling (docs/theory.md §7): picks where a ray's next scattering event happens,
// or that it reaches the end of the segment ("surface"), with probabilities shaped like the
// zero-variance target T(0,t) sigma_s(t) L_i(t) / L(0) (7.1).
//
// This is a pure algorithm over a sequence of bins [t0, t1) along one ray. It knows nothing about
// scenes, media or the guiding field: the caller's walk produces the bins (kd-tree leaves cut at
// medium boundaries / majorant voxels) and fills them with proxy coefficients and cached estimates.
//
// Two samplers share one result type and one mixture pdf:
//  - incremental (§7.3, the paper's Algorithm 1): pulls bins one by one and stops as soon as a
//    scatter is accepted, so its cost grows with the distance to the collision, not the ray length;
//  - tabulated (§7.2): builds the full CDF over all bins plus a surface mass; reference and baseline.
//
// Defensive mixing, Variant A of §7.5 with the chromatic strategies of §7.8: one strategy per query,
// S in {T_R, T_G, T_B, G} with probabilities {c_T q_R, c_T q_G, c_T q_B, 1 - c_T}, where q is the
// caller's channel split (§7.8 uses q = 1/3; callers pass the path throughput, normalised, as the
// spectral MIS of volpath does, §2.6: with a uniform split a chromatic dense medium's weights
// compound over hundreds of events). T_c is ordinary
// free-flight sampling with the proxy extinction of channel c (for grey sigma_t the three coincide);
// G steps with the guided conditional probabilities P^G_k (7.2), clamped and filtered (7.4, 7.6).
// The returned pdf is always the 4-term mixture (7.5), whichever strategy was drawn.
//
// CALLER CONTRACT (weights are not computed here; docs/theory.md §1.4, §7.5 (7.6)):
//  - medium event at t:  beta *= T_hat(0, t) * sigma_s(x_t) / pdf         (per channel)
//  - surface event:      beta *= T_hat(0, s) / pdf                        (pdf = P_surf)
//  where T_hat is the caller's own unbiased transmittance (exact for piecewise-constant media,
//  residual ratio tracking with independent random numbers otherwise, §7.7) and sigma_s is the true
//  local coefficient — never the proxies stored in the bins.
//  - The bins must be contiguous, ordered, finite: clip the ray to the cache / medium bounds and
//    make the last bin end at the surface or exit distance s (an infinite t1 is a caller error,
//    asserted). The exit point plays the role of the surface (environment radiance x T).
//  - Split optically thick bins (proxy sigma_t * length <= ~20) so that P^T_k < 1 in float (§7.6).
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

#include "volguide/core/color.h"

namespace volguide {

// One piece of the ray, with everything the decisions need. Distances are along the ray's unit
// direction (world length); radiances are scalar channel averages of the RGB cache estimates (§7.8).
struct DistanceBin {
    float t0 = 0.f, t1 = 0.f;  // the bin is [t0, t1), distances from the ray origin; t1 >= t0, finite
    Color3 sigma_t{0.f};       // proxy extinction per channel [1/length], constant in the bin (exact
                               // for piecewise-constant media; the super-voxel mean otherwise, §7.7)
    float albedo = 0.f;        // proxy scalar albedo = avg(sigma_s) / avg(sigma_t) of the bin, in [0, 1]
    float inscattered = 0.f;          // L~_i(x(t0), omega): in-scattered radiance towards the ray's origin at
                               // the bin start [W m^-2 sr^-1] (the phase-convolved cache estimate)
    float L = 0.f;             // L~(x(t0), omega): incident radiance at the bin start looking forward
                               // along the ray, i.e. everything ahead on this ray [W m^-2 sr^-1]
    bool valid = true;         // false: the cache has no usable estimate here (e.g. too few samples);
                               // the guided probability then falls back to transmittance, P^G = P^T
    float confidence = 1.f;    // in [0, 1]: P^G := confidence P^G + (1 - confidence) P^T (how far the
                               // guided strategy may depart from free flight in this bin)
};

// The denominator of the guided conditional probability P^G_k = N_k / D_k, N_k = alpha~ (1 - T~_k) L~_i,k.
//  - Incident: D_k = L~^I_k, the (filtered, 7.4) incident radiance at the bin start — the paper's (7.2).
//  - Vre (volguide's default): D_k = N_k + T~_k L~^I_k, the volume rendering equation over the bin
//    with the leaf's own forward lookup as the radiance arriving from beyond the bin (the field is
//    constant per leaf: by its own model that is what lies beyond). Thin bins: the paper's N_k / L~_k
//    to first order in the bin's optical depth. Optically thick bins: -> 1, as free flight, where the
//    paper's form gives alpha L~_i / L~ — whatever the two lookups' disagreement makes it — and so
//    sends guided flights past a bin that lets nothing through (zero-weight paths; in a dense medium
//    at nearly every event). Not exact for consistent estimates beyond first order: the
//    zero-variance oracle (docs/theory.md §14.7) runs on Incident.
enum class DistanceDenominator : uint8_t { Incident, Vre };

struct GuidedDistanceSettings {
    float c_T = 0.5f;  // probability of the transmittance strategies (split over R, G, B by channel_split)
    // Clamp of the guided per-bin probability: P^G_k <= max(p_max, P^T_k) with P^T_k = 1 - T~_k.
    // p_max < 1 keeps later bins reachable by the guided strategy where the bin is thin; in an
    // optically thick bin the guided strategy may scatter as surely as free flight would (a fixed
    // 0.9 there would send 10 % of the guided flights past a bin that lets ~nothing through — a
    // per-event loss that compounds in dense media).
    float p_max = 0.9f;
    float filter_A = 0.5f;  // weight of the new lookup in the incoming-radiance filter (7.4); 1 = off
                            // (Incident denominator only)
    DistanceDenominator denominator = DistanceDenominator::Vre;
    // Per query: how the transmittance share c_T is split over the channels (sums to 1). Callers
    // set it from the path throughput (channel_probabilities, spectral_mis.h).
    Color3 channel_split{1.f / 3.f};
};

enum class DistanceEvent : uint8_t { Medium, Surface };

// The strategy that drove the decisions of one query (only for statistics: the pdf is the mixture).
enum class DistanceStrategy : uint8_t { TransmittanceR, TransmittanceG, TransmittanceB, Guided };

struct DistanceSample {
    DistanceEvent event = DistanceEvent::Surface;
    float t = 0.f;    // medium: the scattering distance; surface: t1 of the last bin (0 without bins)
    float pdf = 1.f;  // medium: mixture density p(t) [1/length] (7.5); surface: P_surf (probability)
    // The mixture's two parts at the sample, pdf = c_T pdf_transmittance + (1 - c_T) pdf_guided
    // (transmittance: the channel split's mixture of T_R, T_G, T_B); the learned selection evaluates
    // other mixtures of them. Negative: not known (tabulated).
    float pdf_transmittance = -1.f, pdf_guided = -1.f;
    int steps = 0;    // bins pulled from the source (zero-length bins included)
    DistanceStrategy strategy = DistanceStrategy::Guided;
    int nan_fallbacks = 0;  // bins whose guided probability was NaN and fell back to P^T (§7.6)
};

// The per-bin arithmetic's helpers (inline: the bins' walk evaluates a bin per leaf crossed).
namespace distance_detail {

// The filter does not extrapolate through a bin that lets less than this through (7.4).
inline constexpr float kFilterMinTransmittance = 1e-4f;

inline bool is_grey(const Color3& c) { return c.r == c.g && c.g == c.b; }
// The scalar proxy of §7.8; exact (not re-rounded) for grey coefficients.
inline float scalar_sigma_t(const Color3& c) { return is_grey(c) ? c.r : c.average(); }

// 1 - exp(-tau) for 0 <= tau < 0.5, the per-bin probability of thin bins: Taylor to degree 9 in
// double (truncation < 3e-10 relative, below float rounding), rounded once to float — as exact as
// libm's expm1f and cheaper per bin (bench_guiding BM_DistanceIncremental; bench/RESULTS.md (issue 35)).
inline float one_minus_exp_small(float tau) {
    const double x = tau;
    double p = 1.0 / 362880.0;
    p = p * -x + 1.0 / 40320.0;
    p = p * -x + 1.0 / 5040.0;
    p = p * -x + 1.0 / 720.0;
    p = p * -x + 1.0 / 120.0;
    p = p * -x + 1.0 / 24.0;
    p = p * -x + 1.0 / 6.0;
    p = p * -x + 0.5;
    p = p * -x + 1.0;
    return float(p * x);
}

// Guided conditional probability (7.2) with the degenerate cases of §7.6.
// p_max is the bin's effective clamp, max(settings.p_max, P^T_k).
inline float guided_probability(float numerator, float denominator, float p_max, bool& nan) {
    nan = std::isnan(numerator) || std::isnan(denominator);
    if (nan) return 0.f;  // the caller substitutes P^T
    if (!(numerator > 0.f)) return 0.f;
    if (!(denominator > 0.f) || std::isinf(denominator)) return p_max;
    return std::min(numerator / denominator, p_max);  // inf / finite = inf -> p_max
}

inline int channel_of(DistanceStrategy s) { return int(s); }

}  // namespace distance_detail

// ---------------------------------------------------------------------------------------------
// Incremental sampler: the per-query state that walks the bins (Variant A). Exposed so that the
// template below and the pdf evaluation share the exact same arithmetic; most callers use
// sample_incremental_distance().
class IncrementalDistanceWalk {
  public:
    // The probabilities of one bin given the bins before it.
    struct Bin {
        float length = 0.f;
        float sigma_bar = 0.f;  // channel-average proxy extinction (drives G's in-bin density)
        float P_T_bar = 0.f;    // 1 - exp(-sigma_bar * length)
        float T_bar = 1.f;      // exp(-sigma_bar * length)
        // 1 - exp(-sigma_t,c * length) of the strategy's channel c (T_c strategies only). The other
        // channels are needed only by the pdf of the accepted bin, which computes them there: per
        // bin the walk pays 2-3 transcendentals instead of 8 (bench_guiding BM_DistanceIncremental).
        float P_T_c = 0.f;
        float P_G = 0.f;  // guided conditional probability after filter, clamps and fallbacks
        float L_I = 0.f;  // filtered incident radiance used as P^G's denominator
        bool nan_fallback = false;
    };

    explicit IncrementalDistanceWalk(const GuidedDistanceSettings& settings,
                                     DistanceStrategy strategy = DistanceStrategy::Guided);

    // Probabilities of `bin`, which must follow the bins already passed to advance().
    Bin evaluate(const DistanceBin& bin) const;
    // The probability the chosen strategy uses to decide "scatter in this bin".
    float decision_probability(const Bin& p) const;
    // Distance in [bin.t0, bin.t1) drawn from the chosen strategy's in-bin density.
    float sample_in_bin(const DistanceBin& bin, const Bin& p, float u) const;
    // Mixture density (7.5) at t inside `bin` (the walk has passed the bins before it).
    float pdf_in_bin(const DistanceBin& bin, const Bin& p, float t) const;
    // Its transmittance and guided parts (pdf_in_bin = c_T first + (1 - c_T) second).
    std::pair<float, float> pdf_parts_in_bin(const DistanceBin& bin, const Bin& p, float t) const;
    // Passes over `bin` without scattering: updates R^T, R^G and the filter state.
    void advance(const DistanceBin& bin, const Bin& p);
    // Mixture probability of passing every bin advanced so far, and its two parts.
    float surface_probability() const;
    std::pair<float, float> surface_parts() const;

    DistanceStrategy strategy() const { return strategy_; }

  private:
    GuidedDistanceSettings settings_;
    DistanceStrategy strategy_;
    Color3 tau_{0.f};  // proxy optical depth of the bins passed: R^T_c = prod (1 - P^T_c) = exp(-tau_c)
    float R_G_ = 1.f;  // prod (1 - P^G)
    // Previous bin, for the filter (7.4).
    bool has_prev_ = false;
    bool prev_valid_ = false;
    float prev_L_I_ = 0.f, prev_T_bar_ = 0.f, prev_albedo_ = 0.f, prev_inscattered_ = 0.f;
};

inline IncrementalDistanceWalk::Bin IncrementalDistanceWalk::evaluate(const DistanceBin& bin) const {
    assert(std::isfinite(bin.t1) && "clip the ray to the cache/medium bounds before sampling");
    Bin p;
    p.length = bin.t1 - bin.t0;
    p.sigma_bar = distance_detail::scalar_sigma_t(bin.sigma_t);
    // One transcendental per bin: thin bins need expm1 for 1 - T (cancellation) and get T = 1 + it
    // (>= 0.6, exact to rounding); thick ones need exp for T (its relative precision when tiny) and
    // get 1 - T (>= 0.4, no cancellation).
    const float tau_bar = p.sigma_bar * p.length;
    if (tau_bar < 0.5f) {
        p.P_T_bar = distance_detail::one_minus_exp_small(tau_bar);
        p.T_bar = 1.f - p.P_T_bar;
    } else {
        p.T_bar = std::exp(-tau_bar);
        p.P_T_bar = 1.f - p.T_bar;
    }
    if (strategy_ != DistanceStrategy::Guided) {
        const int c = distance_detail::channel_of(strategy_);
        p.P_T_c = distance_detail::is_grey(bin.sigma_t) ? p.P_T_bar : -std::expm1(-bin.sigma_t[c] * p.length);
    }

    // Incoming-radiance filter (7.4): extrapolate the previous bin's L^I through it by the VRE
    // bookkeeping L(d_{k-1}) = alpha (1 - T) L_i + T L(d_k), then blend with this bin's lookup.
    p.L_I = bin.L;
    const bool vre = settings_.denominator == DistanceDenominator::Vre;
    const float A = settings_.filter_A;
    if (A < 1.f && has_prev_ && prev_valid_ && std::isfinite(prev_L_I_) &&
        prev_T_bar_ >= distance_detail::kFilterMinTransmittance) {
        const float extrapolated =
            std::max(0.f, (prev_L_I_ - (1.f - prev_T_bar_) * prev_albedo_ * prev_inscattered_) / prev_T_bar_);
        p.L_I = (1.f - A) * extrapolated + A * bin.L;
    }

    if (!bin.valid) {
        p.P_G = p.P_T_bar;
    } else {
        const float numerator = bin.albedo * p.P_T_bar * bin.inscattered;
        float denominator = p.L_I;
        if (vre) denominator = numerator + p.T_bar * p.L_I;
        const float p_max = std::max(settings_.p_max, p.P_T_bar);
        p.P_G = distance_detail::guided_probability(numerator, denominator, p_max, p.nan_fallback);
        if (p.nan_fallback) p.P_G = p.P_T_bar;
        if (bin.confidence < 1.f) p.P_G = bin.confidence * p.P_G + (1.f - bin.confidence) * p.P_T_bar;
    }
    return p;
}

inline float IncrementalDistanceWalk::decision_probability(const Bin& p) const {
    return strategy_ == DistanceStrategy::Guided ? p.P_G : p.P_T_c;
}

inline void IncrementalDistanceWalk::advance(const DistanceBin& bin, const Bin& p) {
    if (!(p.length > 0.f)) return;
    tau_ += bin.sigma_t * p.length;
    R_G_ *= 1.f - p.P_G;
    has_prev_ = true;
    prev_valid_ = bin.valid;
    prev_L_I_ = p.L_I;
    prev_T_bar_ = p.T_bar;
    prev_albedo_ = bin.albedo;
    prev_inscattered_ = bin.inscattered;
}

// Maps one uniform number to a strategy with probabilities {c_T q_R, c_T q_G, c_T q_B, 1 - c_T}.
DistanceStrategy choose_distance_strategy(const GuidedDistanceSettings& settings, float u);

// Samples a distance, pulling bins from `next_bin` (a callable bool(DistanceBin&) that fills the next
// bin and returns false after the last one) and random numbers from `rng.next_1d()` (e.g. Sampler).
// Stops pulling as soon as a scatter is accepted. Random numbers: 1 for the strategy, 1 per
// non-empty bin stepped, 1 for the position in the accepted bin.
// One bin of the incremental sampler (sample_incremental_distance's loop body, for bin sources that
// fuse it into their own walk): true when the query ended in the bin (a medium event, `out` complete).
template <class Rng>
[[gnu::always_inline]] inline bool incremental_step(IncrementalDistanceWalk& walk, const DistanceBin& bin, Rng& rng,
                      const GuidedDistanceSettings& settings, DistanceSample& out) {
    ++out.steps;
    out.t = bin.t1;
    if (!(bin.t1 > bin.t0)) return false;  // zero-length: nothing can happen there
    const IncrementalDistanceWalk::Bin p = walk.evaluate(bin);
    out.nan_fallbacks += p.nan_fallback ? 1 : 0;
    if (rng.next_1d() < walk.decision_probability(p)) {
        out.event = DistanceEvent::Medium;
        out.t = walk.sample_in_bin(bin, p, rng.next_1d());
        std::tie(out.pdf_transmittance, out.pdf_guided) = walk.pdf_parts_in_bin(bin, p, out.t);
        out.pdf = settings.c_T * out.pdf_transmittance + (1.f - settings.c_T) * out.pdf_guided;
        return true;
    }
    walk.advance(bin, p);
    return false;
}

// The query passed every bin: the surface event.
inline void incremental_surface(const IncrementalDistanceWalk& walk, const GuidedDistanceSettings& settings,
                                DistanceSample& out) {
    out.event = DistanceEvent::Surface;
    std::tie(out.pdf_transmittance, out.pdf_guided) = walk.surface_parts();
    out.pdf = settings.c_T * out.pdf_transmittance + (1.f - settings.c_T) * out.pdf_guided;
}

// Samples a distance, pulling bins from `next_bin` (a callable bool(DistanceBin&) that fills the next
// bin and returns false after the last one) and random numbers from `rng.next_1d()` (e.g. Sampler).
// Stops pulling as soon as a scatter is accepted. Random numbers: 1 for the strategy, 1 per
// non-empty bin stepped, 1 for the position in the accepted bin.
template <class NextBin, class Rng>
DistanceSample sample_incremental_distance(NextBin&& next_bin, Rng& rng,
                                           const GuidedDistanceSettings& settings) {
    DistanceSample out;
    IncrementalDistanceWalk walk(settings, choose_distance_strategy(settings, rng.next_1d()));
    out.strategy = walk.strategy();
    DistanceBin bin;
    while (next_bin(bin))
        if (incremental_step(walk, bin, rng, settings, out)) return out;
    incremental_surface(walk, settings, out);
    return out;
}

// The incremental sampler's density at t (0 outside the bins) and its surface probability, for
// given bins: deterministic (the filter only reads cache data), for tests and comparisons.
float incremental_distance_pdf(std::span<const DistanceBin> bins, float t,
                               const GuidedDistanceSettings& settings);
float incremental_surface_probability(std::span<const DistanceBin> bins,
                                      const GuidedDistanceSettings& settings);

// ---------------------------------------------------------------------------------------------
// Tabulated sampler (§7.2): guided bin masses W_k = T~(0,d_k) alpha_k (1 - T~_k) L~_i,k and a surface
// mass W_s = T~(0,s) L~_o, normalised over the whole ray, mixed with the same transmittance
// strategies as above. L~_o is `surface_radiance` when given, else extrapolated from the last bin by
// the VRE bookkeeping of (7.4): max(0, (L~ - alpha (1 - T~) L~_i) / T~). No filter and no clamp: with
// consistent estimates and the filter off it has the incremental sampler's pdf (§14.8).
// Degenerate cases: an invalid bin gets L~_i := the largest L~_i of the valid bins (the guided part
// must not starve an unknown bin); a non-finite mass counts as a NaN fallback and becomes 0; if every
// guided mass is 0 the guided part goes to the surface (as the incremental walk does).
class TabulatedDistance {
  public:
    // Keeps a view of `bins`: they must outlive the object.
    TabulatedDistance(std::span<const DistanceBin> bins, std::optional<float> surface_radiance,
                      const GuidedDistanceSettings& settings);

    // u: strategy, u2: bin / optical depth, u3: position in the bin.
    DistanceSample sample(float u, float u2, float u3) const;
    template <class Rng>
    DistanceSample sample(Rng& rng) const {
        const float u = rng.next_1d(), u2 = rng.next_1d();
        return sample(u, u2, rng.next_1d());
    }
    float pdf(float t) const;
    float surface_probability() const { return P_surf_; }
    int nan_fallbacks() const { return nan_fallbacks_; }

  private:
    int find_bin(float t) const;
    std::span<const DistanceBin> bins_;
    GuidedDistanceSettings settings_;
    std::vector<double> guided_cdf_;  // cdf of the guided masses, bins then the surface (size n + 1)
    std::vector<Color3> tau_;         // per-channel proxy optical depth at each bin start (size n + 1)
    std::vector<float> sigma_bar_;
    double guided_surface_ = 1.0;  // guided surface probability W_s / Z
    float P_surf_ = 1.f;
    int nan_fallbacks_ = 0;
};

// Truncated exponential on [0, length) with rate sigma (2.1); uniform when sigma * length <= 1e-6.
float sample_truncated_exponential(float sigma, float length, float u);
float truncated_exponential_pdf(float sigma, float length, float x);

}  // namespace volguide
