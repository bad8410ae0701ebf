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
// (the path's prefix weight cancels: S = beta f R / q_cur). The learner's CellStatistics
// (cell_statistics.h) sums these terms per cell and decision for every share of kSelectionShares at once
// (one sample serves all).
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
//
// The pilot's unsplit walks also measure what a split would cost: C_0, the decisions of a camera
// sample, over c, the mean decisions that followed a continuation point (what one more branch made
// there costs). Their ratio, continuation_cost_ratio(), sets guided splitting's branch budget
// (roulette_splitting.h).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "volguide/integrators/guided/estimates/cell_statistics.h"

namespace volguide {

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
    std::array<float, kDecisionKinds> kappa = {1.f, 0.25f, 0.25f};
};

class LearnedSelection {
  public:
    static constexpr float kDefault = -1.f;  // share: keep the configured mixture
    LearnedSelection() = default;
    // Learns from the pilot's statistics; `default_share[d]`: the configured guided share of each
    // decision (what the pilot sampled with, where nothing is learned).
    static LearnedSelection fit(const CellStatistics& stats, const SelectionSettings& settings,
                                const std::array<float, kDecisionKinds>& default_share);

    bool empty() const { return cells_.empty(); }
    // Whether any cell has a learned share for decision d (else every share is kDefault).
    bool learned(DecisionKind d) const { return learned_[size_t(d)]; }
    size_t cells() const { return cells_.size(); }
    // The learned guided share in `cell` (kDefault: not learned; cell beyond the table: kDefault).
    float share(DecisionKind d, size_t cell) const {
        return cell < cells_.size() ? cells_[cell].share[size_t(d)] : kDefault;
    }

    // Cells per decision with a learned share of 0 / > 0.
    struct Summary {
        std::array<uint64_t, kDecisionKinds> unguided{}, guided{};
        std::array<double, kDecisionKinds> mean_share{};  // over the learned cells
    };
    Summary summary() const;

    // Little-endian bytes (the prepass state carries them) and back; deserialize throws
    // std::runtime_error on a malformed buffer.
    std::string serialize() const;
    static LearnedSelection deserialize(const std::string& bytes);

    struct Cell {
        std::array<float, kDecisionKinds> share{kDefault, kDefault, kDefault};
    };
    const std::vector<Cell>& table() const { return cells_; }
    // C_0 / c of the pilot (see above); 0: not measured (no camera samples or continuation points).
    float continuation_cost_ratio() const { return cost_ratio_; }

  private:
    void update_learned();
    std::vector<Cell> cells_;
    std::array<bool, kDecisionKinds> learned_{};
    float cost_ratio_ = 0.f;
};

}  // namespace volguide
