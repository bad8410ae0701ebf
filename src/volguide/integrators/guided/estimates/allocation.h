#pragma once
// The allocation (issue 59): per cell of the guiding field (its kd leaves, plus one cell for
// everything outside the field) and per decision — distance, medium direction, surface direction and
// continuation — how much the decision follows the guide: the guided share of the sampling decisions'
// one-sample mixtures q_a = (1 - a) p_u + a p_g (a from kSelectionShares, 0 the unguided decision:
// free flight, the phase function, the BSDF, nothing guided is built or walked), and the continuation's
// rule (the walk's throughput roulette, guided roulette, guided roulette and splitting). Learned while
// rendering: the first pass explores (every decision drawn with the configured mixture), and after
// each pass the allocation is fitted again from all the render's samples so far (cell_statistics.h).
//
// The fit minimises the render's efficiency product V x T (V the pixel estimator's second moment per
// camera sample, (X / I)^2; T the cost per camera sample, the cost model's counted work x weights,
// cost_model.h) by the marginal rule: each cell's choice minimises n_r (m_r(a) / V + c_r(a) / T), with
// m_r(a) the second moment of what follows a decision in cell r under share a (reweighted from the
// samples: one sample serves every share), c_r(a) its cost (its own work under a, guided or unguided,
// and what followed it, reweighted likewise), n_r its decisions per camera sample; V and T are those of
// the choices so far, four rounds. The continuation's rules are compared the same way from what its
// copies collected (cell_statistics.h: E[Y^2], E[Y]^2 per point, the second moment of stochastic-rounded
// splitting). A cell's estimates are shrunk toward its kd parent's (the relative gains a share or a
// rule gives, and the cell's level), with the weight of `prior` samples: few samples follow the
// region around them, many their own.
//
// Exploration: a decision in a cell whose share is 0 cannot measure what a guided share would give
// (p_g is not evaluated), so with probability epsilon (the cell's) a recorded camera sample's decision
// there draws with the configured mixture instead, from a coin independent of the path's random
// numbers: unbiased (each choice is an unbiased estimator) and cheap once epsilon has fallen
// (explore_target / the decisions seen, at least explore_min).
//
// Only probabilities change: any allocation gives an unbiased estimator. The sums are exact (fixed
// point) and the fit is a pure function of them, so the allocation after a pass is the same for any
// thread count.
#include <array>
#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "volguide/core/sampler.h"
#include "volguide/guiding/spatial_tree.h"
#include "volguide/integrators/guided/estimates/cell_statistics.h"

namespace volguide {

// A decision's exploration coin, uniform in [0, 1): a hash of where the decision is made (the point
// and the direction it concerns) and of `salt` (the decision kind), never drawn from the path's
// sampler, so the path's random numbers are the same whether it explores or not, and the coin is
// independent of what the decision then draws.
inline float exploration_coin(const Point3f& p, const Vec3f& d, uint64_t salt) {
    uint64_t h = mix64(salt + 0x2545f4914f6cdd1dULL);
    for (float v : {p.x, p.y, p.z, d.x, d.y, d.z}) h = hash_combine(h, std::bit_cast<uint32_t>(v));
    return float(h >> 40) * 0x1p-24f;
}

struct AllocationSettings {
    // The parent's weight in a cell's estimates, in the cell's own samples (decisions, points).
    double prior = 64.0;
    // Exploration: a cell whose share is 0 explores with probability explore_target / the decisions
    // it has seen (1 before any), at least explore_min.
    double explore_target = 256.0;
    float explore_min = 1.f / 128.f;
    // The share of the render's camera samples that are recorded (guided_volpath records a subset): what a
    // typical sample pays for recording, beside its policy's cost, against the unguided walk, which
    // pays neither (the gain's comparison).
    double recorded_fraction = 1.0;
    // The control samples (the unguided walk's, CellStatistics::add_control_sample) the gain needs before
    // it reads them instead of its first-order extrapolation.
    uint64_t min_control_samples = 256;
    // The mean square of the camera samples' expected x (PixelMoments::mean_square): subtracted from
    // every camera-sample second moment, the fit compares variances (what relMSE measures), not second
    // moments, which on a low-variance image are nearly all the mean's and would leave only the cost.
    double mean_square = 0.0;
};

class Allocation {
  public:
    // A share: the configured mixture (exploration, or nothing learned).
    static constexpr float kConfigured = -1.f;
    // Empty: every decision takes the configured mixture and the configured continuation rule.
    Allocation() = default;
    // Every decision explores (the configured mixture) in each of `cells` cells: a render's first pass.
    static Allocation exploring(size_t cells);
    // Nothing guided in any of `cells` cells, nothing explored (off() is true).
    static Allocation unguided(size_t cells);
    // Fits the allocation to `stats` (cells: the leaves of `tree` + 1).
    static Allocation fit(const CellStatistics& stats, const SpatialTree& tree, const AllocationSettings& settings);

    bool empty() const { return cells_.empty(); }
    size_t cells() const { return cells_.size(); }
    // The share of decision d in `cell` (beyond the table: the configured one) for a decision whose
    // exploration coin is `coin` (uniform in [0, 1), independent of the path's future); `learning`:
    // the camera sample is recorded (only recorded samples explore). kConfigured, 0 or a share.
    float share(DecisionKind d, size_t cell, float coin, bool learning) const;
    // The continuation rule in `cell` (exploring: the configured one, Splitting).
    ContinuationRule rule(size_t cell, float coin, bool learning) const;
    // Whether no decision anywhere follows the guide, nor explores: the unguided walk renders exactly
    // what this allocation does.
    bool off() const;

    // The efficiency gain over the unguided walk, (V T)_unguided / (V T)_guided: measured against the
    // control samples when there are enough (summary().measured), else the fit's prediction for its
    // choices (1: nothing fitted).
    double gain() const { return gain_; }
    // The statistics' C_0 / c (CellStatistics::continuation_cost_ratio): guided splitting's adaptive
    // branch budget (roulette_splitting.h); 0: not measured.
    float continuation_cost_ratio() const { return cost_ratio_; }
    // Per decision kind (the continuation last): the share of the decisions (points) in cells that
    // follow the guide, and of those in cells that explore, weighted by their counts in the fitted
    // statistics.
    struct Summary {
        std::array<double, kDecisionKinds + 1> guided{}, exploring{};
        // The prediction's two factors: the unguided walk's second moment over the allocation's, and
        // the allocation's cost over the unguided walk's (predicted gain = moments / cost).
        double predicted_moment_ratio = 0.0, predicted_cost_ratio = 0.0, predicted_gain = 1.0;
        bool measured = false;  // whether gain() is the control samples' (else the prediction)
    };
    const Summary& summary() const { return summary_; }
    // --stats names of the summary and the prediction.
    std::vector<std::pair<std::string, double>> named() const;

    // Little-endian bytes (the pre-pass and the checkpoint carry them) and back; deserialize throws
    // std::runtime_error on malformed bytes.
    std::string serialize() const;
    static Allocation deserialize(const std::string& bytes);

    struct Cell {
        std::array<float, kDecisionKinds> share{kConfigured, kConfigured, kConfigured};
        std::array<float, kDecisionKinds + 1> explore{1.f, 1.f, 1.f, 1.f};
        ContinuationRule rule = ContinuationRule::Splitting;
    };
    const std::vector<Cell>& table() const { return cells_; }

  private:
    std::vector<Cell> cells_;
    double gain_ = 1.0;
    float cost_ratio_ = 0.f;
    Summary summary_;
};

}  // namespace volguide
