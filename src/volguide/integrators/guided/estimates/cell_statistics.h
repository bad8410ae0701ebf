#pragma once
// What guided_volpath learns from camera samples between passes (the learned selection's pilot, before
// the render; rrs=ears, from the render's own passes): one statistic per cell of the guiding field (its
// kd leaves, plus one cell for everything outside the field), filled by one recorder (cell_recorder.h)
// and read by the two consumers (learned_selection.h, continuation_snapshot.h):
//  - per cell and sampling decision (distance, medium direction, surface direction), the second moments
//    M(a) of what followed the decision under every guided share a of kSelectionShares (the selection);
//  - per cell, continuation stage and direction bin, the first and second moments of what a
//    continuation collected per unit path weight and its cost (ears);
//  - per camera sample, its relative value's second moment (X / I)^2, its cost and branches;
//  - per pixel, the moments of X / I (PixelMoments).
// One cost unit: the sampling decisions a path makes (a distance, direction or surface decision each;
// NEE and intersections follow them in proportion), counted, never timed: the same for any thread
// count.
//
// Exact sums: every sum is an integer (counts) or a fixed-point integer (ExactSum, non-negative terms),
// so the totals do not depend on the order the threads add them in.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "volguide/core/vec.h"
#include "volguide/integrators/volpath/walk_policy.h"

namespace volguide {

// The sampling decisions the selection learns a share for (walk_policy.h's DecisionKind).
inline constexpr int kDecisionKinds = 3;
// The guided shares whose second moments every decision adds to.
inline constexpr std::array<float, 6> kSelectionShares = {0.f, 0.1f, 0.25f, 0.5f, 0.75f, 0.9f};

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

  private:
    void add_words(uint64_t hi, uint64_t lo);
    uint64_t hi_ = 0, lo_ = 0;
};

// One cell's decisions of one kind: for each share a, the sum of (S / I)^2 q_cur / q_a (S what followed
// the decision, q_a the mixture density at share a); the sum at the share sampled with; their count.
struct DecisionMoments {
    std::array<ExactSum, kSelectionShares.size()> m;
    ExactSum current;
    uint64_t count = 0;
    DecisionMoments& operator+=(const DecisionMoments& o);
};

// What the continuations of one (stage, cell, bin) collected: n samples y (per unit weight), their
// sum and sum of squares, and their summed cost in decisions.
struct ContinuationMoments {
    uint64_t n = 0;
    ExactSum sum, sum_sq;
    uint64_t cost = 0;
    ContinuationMoments& operator+=(const ContinuationMoments& o);
};

class CellStatistics {
  public:
    CellStatistics() = default;
    // `cells`: the field's leaves + 1 (the last: outside the field or no leaf known).
    explicit CellStatistics(size_t cells);
    size_t cells() const { return cells_; }

    // One decision in `cell` sampled with density q_cur, whose unguided and guided densities at the
    // sample are p_u and p_g; s2 = (S / I)^2 of what followed it.
    void add_decision(DecisionKind d, size_t cell, double s2, float q_cur, float p_u, float p_g);
    // A continuation of `stage` in `cell` and direction bin `bin` collected y per unit weight and cost
    // `cost` decisions.
    void add_continuation(ContinuationStage stage, size_t cell, int bin, double y, uint64_t cost);
    // A camera sample of relative value x = X / I (s2 = x^2) that made `cost` decisions, `unrecorded` of
    // them without a guided mixture, in `branches` branches.
    void add_camera_sample(double s2, uint64_t cost, uint64_t unrecorded, int branches);

    const DecisionMoments& decision(DecisionKind d, size_t cell) const {
        return decisions_[cell * size_t(kDecisionKinds) + size_t(d)];
    }
    const ContinuationMoments& continuation(ContinuationStage stage, size_t cell, int bin) const {
        return continuations_[index(stage, cell, bin)];
    }
    uint64_t camera_samples() const { return camera_samples_; }
    double camera_moment() const { return camera_moment_.value(); }
    uint64_t cost() const { return cost_; }
    uint64_t unrecorded_decisions() const { return unrecorded_; }
    uint64_t branches() const { return branches_; }
    // Zeroes every sum (keeps the size).
    void clear();
    CellStatistics& operator+=(const CellStatistics& o);

  private:
    size_t index(ContinuationStage stage, size_t cell, int bin) const {
        return (size_t(stage) * cells_ + cell) * size_t(kContinuationDirectionBins) + size_t(bin);
    }
    size_t cells_ = 0;
    std::vector<DecisionMoments> decisions_;
    std::vector<ContinuationMoments> continuations_;
    uint64_t camera_samples_ = 0, cost_ = 0, unrecorded_ = 0, branches_ = 0;
    ExactSum camera_moment_;
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
    struct Pixel {
        double n = 0, sum = 0, sum_sq = 0;
        // The pixel's mean x shrunk towards 1 by `prior` samples: (prior + sum) / (prior + n).
        float correction(double prior) const;
    };
    // The sums of pixel p (row-major); read between passes.
    Pixel at(size_t p) const;
    void clear();

  private:
    int width_ = 0, height_ = 0;
    std::unique_ptr<std::atomic<int64_t>[]> sum_, sum_sq_;
    std::unique_ptr<std::atomic<uint32_t>[]> count_;
};

}  // namespace volguide
