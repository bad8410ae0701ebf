#pragma once
// Guided Russian roulette and splitting (docs/theory.md §9): after a guided decision, the partial path's
// expected contribution E[X] = <w * Psi~> (w its weight, Psi~ the field's estimate of what the
// continuation collects) is compared with the pixel's estimated value I. The ratio r = E[X] / I is
// turned into an expected number of continuations q by the weight window of size s (eq. 9.1):
// s = 1 is the paper's q = r, s = 5 the ADRRS window (no decision for r in [1/3, 5/3]). q is
// clamped to [q_min, q_max] and to the branches the camera sample may still create; the number of
// continuations is n = floor(q + xi) (E[n] = q) and each carries the weight 1/q, so any q gives an
// unbiased estimator (§9.4, §9.6). Only grr: q <= 1 (no splitting).
//
// Branch budget (issue 21; by default adaptive, issue 55): the camera sample starts with an allowance of B
// branches; a decision may split into at most floor(allowance) copies (q <= floor(allowance)), and
// the n copies of a split share their path's allowance, a / n each (the walk divides it). The
// allowances of the live branches always sum to at most B and each is >= 1, so a camera sample can
// never make more than B branches, wherever the estimates are wrong — bounded by construction,
// spread over the path tree, instead of the first branches spending the cap. Only q is limited:
// every decision stays unbiased.
//
// The adaptive budget (branch_budget = 0, the default) bounds a camera sample by its cost: it may cost
// about kBudgetFactor x what an unsplit one costs, B = kBudgetFactor x C_0 / c with C_0 the cost of a
// camera sample and c the mean cost of what followed a continuation point's copy (what one more branch
// made there costs), both measured by guided_volpath's allocation from counted work (its statistics,
// cost_model.h), so B is the same for any thread count, and stored with the allocation, so chunks
// rendered from a training file use the same B. Within [kMinBudget, max_branches]; kDefaultBudget before
// anything is measured. Before, the
// splitting was bounded only by the cap (64), which dense scenes reached for little gain per sample
// (bench/RESULTS.md, issue 55).
//
// Statistics (kills, splits, branches per camera sample with its distribution) are counted per
// thread and summed on request.
#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "volguide/core/color.h"

namespace volguide {

// Ears: efficiency-aware RR and splitting (docs/theory.md §9.8); its factor comes from learned
// statistics (the integrator's), and bound() applies the same clamps and branch bounds to it.
enum class RouletteMode { Standard, Guided, GuidedSplitting, Ears };

struct RouletteSplittingSettings {
    RouletteMode mode = RouletteMode::Standard;
    // s >= 1: 1 the paper's q = E[X]/I, 5 ADRRS (the default: at equal time it beat or tied s = 1
    // on the benchmark scenes and kept the branches per camera sample under the cap where s = 1
    // reached it; measured: see bench/RESULTS.md (issue 35)).
    float window = 5.f;
    float q_min = 0.1f, q_max = 20.f;
    // Path branches per camera sample, the original included: the fixed ceiling whatever the budget.
    int max_branches = 16;
    float branch_budget = 0.f;  // B >= 1: the allowance of a camera sample; 0: adaptive (see above)
};

// The weight-window factor q(r) of eq. 9.1 before clamping (r >= 0).
float weight_window_factor(float r, float window);

// Continuations of a decision with expected count q: floor(q + u), u in [0, 1).
inline int stochastic_round(float q, float u) { return int(q + u); }

struct RouletteSplittingStats {
    uint64_t decisions = 0;          // guided RR/splitting decisions (q computed)
    uint64_t invalid_estimates = 0;  // decisions without a usable estimate (q = 1)
    uint64_t kills = 0;              // decisions that ended the path (n = 0)
    uint64_t splits = 0;             // decisions that continued with n > 1
    uint64_t extra_branches = 0;     // sum of n - 1 over the splits
    uint64_t cap_limited = 0;        // decisions whose q was lowered by the branch cap
    uint64_t budget_limited = 0;     // decisions whose q was lowered by the branch's allowance
    uint64_t unlearned = 0;          // ears: continuation points without enough statistics (no decision)
    uint64_t camera_samples = 0;
    // branch_histogram[k]: camera samples that made k branches (k = 0 unused; the last bin is the cap)
    std::vector<uint64_t> branch_histogram;
    double pixel_estimate_seconds = 0;
    float branch_budget = 0.f;  // a camera sample's allowance (initial_allowance())
    float largest_branch_budget = 0.f;  // ... the largest of the render's passes (the budget is re-measured between them)
    RouletteSplittingStats& operator+=(const RouletteSplittingStats& o);
    // Smallest k such that at least `fraction` of the camera samples made <= k branches.
    int branches_quantile(double fraction) const;
    std::vector<std::pair<std::string, double>> named() const;
};

class RouletteSplitting {
  public:
    explicit RouletteSplitting(const RouletteSplittingSettings& settings);
    const RouletteSplittingSettings& settings() const { return settings_; }
    bool splits() const {
        return settings_.mode == RouletteMode::GuidedSplitting || settings_.mode == RouletteMode::Ears;
    }

    // The expected number of continuations of a path of weight `weight` whose continuation is
    // estimated at `estimate`, in a pixel estimated at `pixel` (> 0), when the camera sample has
    // `branches` branches so far and this branch has the allowance `allowance` (branch budget; +inf
    // when off): 1 when the estimate is unusable (zero, not finite). Counts the decision.
    float factor(const Color3& weight, const Color3& estimate, float pixel, int branches,
                 float allowance = std::numeric_limits<float>::infinity()) const;
    // A factor q computed elsewhere (ears) clamped to [q_min, q_max] and bounded as factor() bounds
    // it (the cap, the allowance). Counts the decision.
    float bound(float q, int branches, float allowance = std::numeric_limits<float>::infinity()) const;
    // Counts a continuation point where the factor's statistics were too few (ears).
    void count_unlearned() const;
    static constexpr float kBudgetFactor = 2.f, kMinBudget = 2.f, kDefaultBudget = 4.f;
    // A camera sample's allowance: the branch budget B (fixed, or adaptive; within max_branches).
    float initial_allowance() const {
        return std::min(settings_.branch_budget >= 1.f ? settings_.branch_budget : adaptive_budget_,
                        float(settings_.max_branches));
    }
    // The adaptive budget from the measured C_0 / c (cell_statistics.h; <= 0: not measured, the default);
    // set between passes.
    void set_cost_ratio(float ratio);
    // Counts a decision's outcome: n continuations.
    void count_outcome(int n) const;
    // Counts a finished camera sample that made `branches` branches.
    void count_camera_sample(int branches) const;

    void set_pixel_estimate_seconds(double s) { pixel_estimate_seconds_ = s; }
    RouletteSplittingStats stats() const;

  private:
    float bounded(float q, int branches, float allowance, RouletteSplittingStats& st) const;
    RouletteSplittingSettings settings_;
    float adaptive_budget_ = kDefaultBudget;
    float largest_budget_;  // of initial_allowance() over the budgets set so far (the first included)
    double pixel_estimate_seconds_ = 0;
    mutable tbb::enumerable_thread_specific<RouletteSplittingStats> stats_;
};

}  // namespace volguide
