#pragma once
// Learned selection (issue 21): per cell of the guiding field (its kd leaves, plus one cell for
// everything outside the field), how much each guided decision is trusted — the guided share of the
// distance decision's mixture (1 - c_T), of the medium direction mixture (1 - phase_prob) and of
// the diffuse surface mixture (1 - bsdf_prob). Learned from a pilot: a few camera samples per pixel
// with the configured mixtures, after training.
//
// The mixtures: every decision is a one-sample mixture q_a = (1 - a) p_u + a p_g of the unguided
// (p_u: free flight, phase function, BSDF) and the guided density p_g, with guided share a. For one
// decision sampled from q_cur, with S the contribution of everything after it to the camera sample
// and I the pixel estimate, the pixel's second moment attributable to it under share a is
//   M(a) = E_cur[(S / I)^2 q_cur / q_a]
// (the path's prefix weight cancels: S = beta f R / q_cur). SelectionStatistics sums these terms
// per cell and decision for every share of kSelectionShares at once (one sample serves all).
// fit() then picks per cell the share that minimises the render's variance x time:
//   argmin_a  M_r(a) / V + n_r kappa [a > 0] / T,
// V the pixel estimator's second moment (the pilot's sum of (X / I)^2 over camera samples, X the
// camera sample's value; a decision's choice changes the second moment of what follows it by
// M_r(a) - M_r(pilot's), and nothing before it; these changes do not add up over the decisions of
// one path, each of whose M counts everything after it, so V stays the pilot's), T the
// cost in decisions (each decision 1, a guided one 1 + kappa of its kind, SelectionSettings): the
// marginal rule of minimising V x T over independent cells, iterated three times. A cell that loses with guiding gets share 0:
// the walk then makes volpath's decision there and pays nothing for guiding (no walk over bins, no
// product built).
//
// Only probabilities change: any learned value gives an unbiased estimator. Sums are exact
// (fixed point, 128-bit integers), so the result is independent of the order the pilot's samples
// arrive in, hence of the thread count. Cells with fewer than min_samples pilot decisions keep the
// configured mixture (kDefault).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace volguide {

enum class SelectionDecision : uint8_t { Distance = 0, Direction = 1, Surface = 2 };
inline constexpr int kSelectionDecisions = 3;
// The guided shares the pilot evaluates.
inline constexpr std::array<float, 6> kSelectionShares = {0.f, 0.1f, 0.25f, 0.5f, 0.75f, 0.9f};

struct SelectionSettings {
    int pilot_spp = 2;  // camera samples per pixel of the pilot (0: no learned selection)
    int min_samples = 32;  // pilot decisions a cell needs before its choice is learned
    // Weight, in pilot decisions, of the mean pooled over all cells in each cell's mean second
    // moment per decision (shrinkage of noisy per-cell estimates, fit()).
    float prior_samples = 256.f;
    // Extra cost of a guided decision, in units of an unguided one (distance, direction, surface):
    // guided distance decisions switched off almost everywhere in thin fog saved a quarter of the
    // render time at equal spp, which these units reproduce (bench/RESULTS.md (issue 35)). Without the
    // shrinkage of fit() a short pilot's per-cell moments are too noisy to weigh against a cost.
    std::array<float, kSelectionDecisions> kappa = {1.f, 0.25f, 0.25f};
};

// An exact sum of non-negative terms: fixed point with 2^-32 resolution in 128 bits (two words),
// each term clamped to 1e15.
class ExactSum {
  public:
    void add(double term);
    ExactSum& operator+=(const ExactSum& o);
    double value() const;

  private:
    void add_words(uint64_t hi, uint64_t lo);
    uint64_t hi_ = 0, lo_ = 0;
};

class SelectionStatistics {
  public:
    SelectionStatistics() = default;
    // `cells`: the field's leaves + 1 (the last: outside the field).
    explicit SelectionStatistics(size_t cells);
    size_t cells() const { return moments_.size(); }

    // One decision in `cell` sampled with density q_cur, whose unguided and guided densities at
    // the sample are p_u and p_g; s2 = (S / I)^2 of what followed it.
    void add_decision(SelectionDecision d, size_t cell, double s2, float q_cur, float p_u, float p_g);
    // Every decision of the pilot's walks, recorded or not (the cost model's unit).
    void add_unrecorded_decisions(uint64_t n) { unrecorded_ += n; }
    // A camera sample of value X in a pixel of estimate I: s2 = (X / I)^2.
    void add_camera_sample(double s2);

    SelectionStatistics& operator+=(const SelectionStatistics& o);

    struct Moments {
        std::array<ExactSum, kSelectionShares.size()> m;
        ExactSum current;  // sum of s2: M at the share the pilot sampled with
        uint64_t count = 0;
    };
    const Moments& moments(SelectionDecision d, size_t cell) const { return moments_[cell][size_t(d)]; }
    uint64_t unrecorded_decisions() const { return unrecorded_; }
    uint64_t camera_samples() const { return camera_samples_; }
    double camera_moment() const { return camera_moment_.value(); }

  private:
    std::vector<std::array<Moments, kSelectionDecisions>> moments_;
    uint64_t unrecorded_ = 0;
    uint64_t camera_samples_ = 0;
    ExactSum camera_moment_;
};

class LearnedSelection {
  public:
    static constexpr float kDefault = -1.f;  // share: keep the configured mixture
    LearnedSelection() = default;
    // Learns from the pilot's statistics; `default_share[d]`: the configured guided share of each
    // decision (what the pilot sampled with, where nothing is learned).
    static LearnedSelection fit(const SelectionStatistics& stats, const SelectionSettings& settings,
                                const std::array<float, kSelectionDecisions>& default_share);

    bool empty() const { return cells_.empty(); }
    // Whether any cell has a learned share for decision d (else every share is kDefault).
    bool learned(SelectionDecision d) const { return learned_[size_t(d)]; }
    size_t cells() const { return cells_.size(); }
    // The learned guided share in `cell` (kDefault: not learned; cell beyond the table: kDefault).
    float share(SelectionDecision d, size_t cell) const {
        return cell < cells_.size() ? cells_[cell].share[size_t(d)] : kDefault;
    }

    // Cells per decision with a learned share of 0 / > 0.
    struct Summary {
        std::array<uint64_t, kSelectionDecisions> unguided{}, guided{};
        std::array<double, kSelectionDecisions> mean_share{};  // over the learned cells
    };
    Summary summary() const;

    // Little-endian bytes (the prepass state carries them) and back; deserialize throws
    // std::runtime_error on a malformed buffer.
    std::string serialize() const;
    static LearnedSelection deserialize(const std::string& bytes);

    struct Cell {
        std::array<float, kSelectionDecisions> share{kDefault, kDefault, kDefault};
    };
    const std::vector<Cell>& table() const { return cells_; }

  private:
    void update_learned();
    std::vector<Cell> cells_;
    std::array<bool, kSelectionDecisions> learned_{};
};

}  // namespace volguide
