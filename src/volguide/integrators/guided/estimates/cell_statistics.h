#pragma once
// What guided_volpath learns from its own camera samples (the render's passes, and the learning
// passes of a pre-pass that is saved for other processes): one statistic per cell of the guiding
// field (its kd leaves, plus one cell for everything outside the field), filled by one recorder
// (cell_recorder.h) and read by the allocation (allocation.h) and by rrs=ears (continuation_snapshot.h):
//  - per cell and sampling decision (distance, medium direction, surface direction): the second
//    moments M(a) of what followed the decision under every guided share a of kSelectionShares, the
//    cost of what followed it under every share, and the decision's own cost guided and unguided;
//  - per cell, the continuation points' second moments and costs under the unguided continuation
//    (the walk's throughput roulette) and under the guided rule (guided RR and splitting);
//  - per cell, continuation stage and direction bin, the first and second moments of what a
//    continuation collected per unit path weight and its cost (ears);
//  - per camera sample, its relative value's second moment (X / I)^2, its cost and branches;
//  - per pixel, the moments of X / I (PixelMoments).
// Costs are the cost model's (cost_model.h): counted work times fitted weights, in ns, never timed.
//
// Exact sums: every sum is an integer (counts) or a fixed-point integer (ExactSum, non-negative terms),
// so the totals do not depend on the order the threads add them in, and they are stored exactly
// (serialize: a checkpoint resumes with the same statistics, bit for bit).
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "volguide/core/vec.h"
#include "volguide/integrators/volpath/walk_policy.h"

namespace volguide {

// The sampling decisions the allocation learns a share for (walk_policy.h's DecisionKind).
inline constexpr int kDecisionKinds = 3;
// The guided shares whose second moments every decision adds to (the allocation chooses among them).
inline constexpr std::array<float, 6> kSelectionShares = {0.f, 0.1f, 0.25f, 0.5f, 0.75f, 0.9f};
inline constexpr size_t kShares = kSelectionShares.size();

// The coarse direction bins of the continuation moments: the six faces of the cube map (the dominant
// axis and its sign), 0..5.
inline constexpr int kContinuationDirectionBins = 6;
// The continuation stages kept apart (walk_policy.h's ContinuationStage).
inline constexpr int kContinuationStages = 3;
int continuation_direction_bin(const Vec3f& w);

// An exact sum of non-negative terms: fixed point with 2^-32 resolution in 128 bits (two words),
// each term clamped to 1e15.
class ExactSum {
  public:
    void add(double term);
    ExactSum& operator+=(const ExactSum& o);
    double value() const;
    uint64_t hi() const { return hi_; }
    uint64_t lo() const { return lo_; }
    static ExactSum from_words(uint64_t hi, uint64_t lo);

  private:
    void add_words(uint64_t hi, uint64_t lo);
    uint64_t hi_ = 0, lo_ = 0;
};

// One decision as the recorder saw it: in `cell`, S^2 / I^2 = s2 of what followed it, the cost of what
// followed it (`after`), its own cost (`own`) and what the unguided decision would have cost there
// (`own_unguided`). `mixture`: drawn from q_cur = (1 - a) p_u + a p_g with both densities known at the
// sample (a guided share > 0); otherwise an unguided decision (q_cur = p_u, p_g not known).
struct DecisionSample {
    size_t cell = 0;
    double s2 = 0.0;
    bool mixture = false;
    float q_cur = 0.f, p_u = 0.f, p_g = 0.f;
    double own = 0.0, own_unguided = 0.0, after = 0.0;
};

// One cell's decisions of one kind.
struct DecisionMoments {
    // Decisions drawn from a known mixture: for each share a, the sums of s2 q_cur / q_a (their second
    // moment had they been drawn with share a) and of after q_a / q_cur (what followed them would have
    // cost); the sum of s2 at the share sampled with; of their own cost and what the unguided decision
    // would have cost; their count.
    std::array<ExactSum, kShares> m, after;
    ExactSum current, current_after, own, own_unguided;
    uint64_t count = 0;
    // Unguided decisions (share 0): their count and sums of s2, own cost and cost of what followed.
    uint64_t unguided = 0;
    ExactSum unguided_m, unguided_own, unguided_after;
    DecisionMoments& operator+=(const DecisionMoments& o);
};

// The continuation rules a region chooses among: the walk's throughput roulette, guided roulette
// alone (the guided factor capped at 1) and guided roulette and splitting.
enum class ContinuationRule : uint8_t { Unguided = 0, Roulette = 1, Splitting = 2 };
inline constexpr int kContinuationRules = 3;

// One continuation point as the recorder saw it: in `cell`, with the path weight before its decision
// relative to the pixel estimate (b = beta / I), the factor it was decided with (q_cur) and the
// factors of the unguided and the guided rule there (guided_known false: not computed), and, from its n >= 1
// copies' values y per unit weight: a2 = E[Y^2] and b2 = E[Y]^2 (from the copies' products; a2 when
// n = 1), and the mean cost of a copy's continuation. Points killed by the roulette are represented by
// the survivors (their weight 1 / q_cur when q_cur < 1).
struct ContinuationSample {
    size_t cell = 0;
    double b = 0.0;
    float q_cur = 1.f, q_unguided = 1.f, q_guided = 1.f;
    bool guided_known = false;
    double a2 = 0.0, b2 = 0.0, copy_cost = 0.0;
};

// One cell's continuation points: for those where the guided rule's factor is known, the weighted
// count and the sums of the second moment and the cost under each rule; for the others, the same
// under the unguided rule only; for all, the second moment and cost as decided.
struct ContinuationChoiceMoments {
    ExactSum known_points;
    std::array<ExactSum, kContinuationRules> known_m, known_c;
    ExactSum other_points, other_m, other_c;
    ExactSum current_m, current_c;
    ContinuationChoiceMoments& operator+=(const ContinuationChoiceMoments& o);
};

// The second moment (relative to I^2) of a continuation point's subtree under the factor q (b, a2, b2
// as in ContinuationSample): b^2 (a2 / q + E[n (n - 1)] b2 / q^2) for n drawn by stochastic rounding.
double continuation_second_moment(double b, double a2, double b2, double q);

// What the continuations of one (stage, cell, bin) collected: n samples y (per unit weight), their
// sum and sum of squares, and their summed cost (ears).
struct ContinuationMoments {
    uint64_t n = 0;
    ExactSum sum, sum_sq, cost;
    ContinuationMoments& operator+=(const ContinuationMoments& o);
};

// What a camera sample's cost holds beside its decisions': its recording and its walk's policy (nothing
// the unguided walk pays).
struct SampleOverhead {
    double recording = 0.0, policy = 0.0;
};

class CellStatistics {
  public:
    CellStatistics() = default;
    // `cells`: the field's leaves + 1 (the last: outside the field or no leaf known).
    explicit CellStatistics(size_t cells);
    size_t cells() const { return cells_; }

    void add_decision(DecisionKind d, const DecisionSample& s);
    void add_continuation_point(const ContinuationSample& s);
    // A continuation of `stage` in `cell` and direction bin `bin` collected y per unit weight and cost
    // `cost` (ears).
    void add_continuation(ContinuationStage stage, size_t cell, int bin, double y, double cost);
    // A camera sample of relative value x = X / I (s2 = x^2) that cost `cost`, in `branches` branches;
    // of its cost, what its recording and its walk's policy cost (`overhead`).
    void add_camera_sample(double s2, double cost, int branches, const SampleOverhead& overhead = SampleOverhead());
    // A control sample: a camera sample the unguided walk rendered (no policy, nothing recorded but this)
    // of relative value x (s2 = x^2) and cost `cost`; the allocation's gain compares with these directly.
    void add_control_sample(double s2, double cost);

    const DecisionMoments& decision(DecisionKind d, size_t cell) const {
        return decisions_[cell * size_t(kDecisionKinds) + size_t(d)];
    }
    const ContinuationChoiceMoments& continuation_choice(size_t cell) const { return choices_[cell]; }
    const ContinuationMoments& continuation(ContinuationStage stage, size_t cell, int bin) const {
        return continuations_[index(stage, cell, bin)];
    }
    uint64_t camera_samples() const { return camera_samples_; }
    double camera_moment() const { return camera_moment_.value(); }
    double cost() const { return cost_.value(); }
    double recording_cost() const { return recording_.value(); }
    double policy_cost() const { return policy_.value(); }
    uint64_t branches() const { return branches_; }
    uint64_t control_samples() const { return control_samples_; }
    double control_moment() const { return control_moment_.value(); }
    double control_cost() const { return control_cost_.value(); }
    // C_0 / c: a camera sample's cost over the mean cost of what followed a continuation point's copy
    // (what one more branch made there costs): guided splitting's adaptive branch budget reads it
    // (roulette_splitting.h). 0: not measured.
    double continuation_cost_ratio() const;
    // Zeroes every sum (keeps the size).
    void clear();
    CellStatistics& operator+=(const CellStatistics& o);

    // Little-endian bytes, every sum exactly, and back (throws std::runtime_error on malformed bytes).
    std::string serialize() const;
    static CellStatistics deserialize(const std::string& bytes);

  private:
    size_t index(ContinuationStage stage, size_t cell, int bin) const {
        return (size_t(stage) * cells_ + cell) * size_t(kContinuationDirectionBins) + size_t(bin);
    }
    size_t cells_ = 0;
    std::vector<DecisionMoments> decisions_;
    std::vector<ContinuationChoiceMoments> choices_;
    std::vector<ContinuationMoments> continuations_;
    uint64_t camera_samples_ = 0, branches_ = 0, control_samples_ = 0;
    ExactSum camera_moment_, cost_, recording_, policy_, control_moment_, control_cost_;
};

// Per pixel of the film, the count and moments of the relative samples x = X / I, added from any
// thread (atomic fixed-point integers: exact, any order). x is clamped to [0, 1e5] (a statistic of the
// decisions, never a weight).
class PixelMoments {
  public:
    PixelMoments() = default;
    PixelMoments(int width, int height);
    int width() const { return width_; }
    int height() const { return height_; }
    // The pixel of a film position, -1 outside the film (a filter's border).
    long pixel(Point2f film_uv) const;
    void add(long pixel, double x);
    // Adds another film's sums (same size; between passes).
    PixelMoments& operator+=(const PixelMoments& o);
    struct Pixel {
        double n = 0, sum = 0, sum_sq = 0;
        // The pixel's mean x shrunk towards 1 by `prior` samples: (prior + sum) / (prior + n).
        float correction(double prior) const;
    };
    // The sums of pixel p (row-major); read between passes.
    Pixel at(size_t p) const;
    // Over the samples, the mean of their pixel's squared mean x (each pixel's unbiased from its sums,
    // pixels of fewer than two samples left out): what every unbiased sampler's second moment of x holds
    // beside its variance (Allocation::fit subtracts it).
    double mean_square() const;
    // Little-endian bytes of every pixel's sums (exactly), and back into a film of the same size (throws
    // std::runtime_error on malformed bytes or another size): a checkpoint's.
    std::string serialize() const;
    void restore(const std::string& bytes);
    void clear();

  private:
    int width_ = 0, height_ = 0;
    std::unique_ptr<std::atomic<int64_t>[]> sum_, sum_sq_;
    std::unique_ptr<std::atomic<uint32_t>[]> count_;
};

}  // namespace volguide
