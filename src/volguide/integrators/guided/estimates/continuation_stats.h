#pragma once
// What efficiency-aware RR and splitting (rrs=ears, docs/theory.md §9.8) learns from the render's own
// passes: per leaf of the guiding field x direction bin x continuation stage, the first and second
// moments of what a medium vertex's continuation collects per unit path weight and its cost (the path
// events it made); per camera sample its cost and branches, per pixel the moments of the relative
// sample X / I (I: the pixel estimate), whence the image's relative variance V and cost C per sample.
//
// Exact sums: every sum is an integer (event counts) or a fixed-point integer (guiding/selection.h's
// ExactSum, non-negative terms), so the totals do not depend on the order the threads add them in, and
// the image is the same for any thread count. The decisions of a pass read a ContinuationSnapshot
// frozen between passes (end_pass), never the sums being filled: within a pass every q is a fixed
// function of the path, so every decision stays unbiased (§9.4) whatever the statistics are.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "volguide/core/vec.h"
#include "volguide/integrators/guided/estimates/learned_selection.h"  // ExactSum
#include "volguide/integrators/volpath/walk_policy.h"

namespace volguide {

// The coarse direction bins of the statistics: the six faces of the cube map (the dominant axis and
// its sign), 0..5.
constexpr int kContinuationDirectionBins = 6;
// The continuation stages the statistics keep apart (walk_policy.h's ContinuationStage).
constexpr int kContinuationStages = 3;
int continuation_direction_bin(const Vec3f& w);

// What the continuations of one (stage, cell, bin) collected: n samples y (per unit weight), their
// sum and sum of squares, and their summed cost in path events.
struct ContinuationMoments {
    uint64_t n = 0;
    ExactSum sum, sum_sq;
    uint64_t cost = 0;
    ContinuationMoments& operator+=(const ContinuationMoments& o);
};

class ContinuationStatistics {
  public:
    ContinuationStatistics() = default;
    // `cells`: the field's leaves + 1 (the last: outside the field or no leaf known).
    explicit ContinuationStatistics(size_t cells);
    size_t cells() const { return cells_; }

    // A continuation of `stage` in `cell` and direction bin `bin` collected y per unit weight and made
    // `cost` events.
    void add_point(ContinuationStage stage, size_t cell, int bin, double y, uint64_t cost);
    // A camera sample that made `cost` events in `branches` branches.
    void add_camera_sample(uint64_t cost, int branches);
    const ContinuationMoments& moments(ContinuationStage stage, size_t cell, int bin) const {
        return moments_[index(stage, cell, bin)];
    }
    uint64_t camera_samples() const { return camera_samples_; }
    uint64_t cost() const { return cost_; }
    uint64_t branches() const { return branches_; }
    // Zeroes every sum (keeps the size).
    void clear();
    ContinuationStatistics& operator+=(const ContinuationStatistics& o);

  private:
    size_t index(ContinuationStage stage, size_t cell, int bin) const {
        return (size_t(stage) * cells_ + cell) * size_t(kContinuationDirectionBins) + size_t(bin);
    }
    size_t cells_ = 0;
    std::vector<ContinuationMoments> moments_;
    uint64_t camera_samples_ = 0, cost_ = 0, branches_ = 0;
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

struct EarsSettings {
    // Continuations a (stage, cell, bin) needs before its moments are used; fewer: the fallback.
    uint64_t min_samples = 32;
    // The adaptive branch budget: a camera sample may cost about budget_factor x what an unsplit one
    // cost (the first pass, made before any statistics), in branches B = budget_factor x C_0 / c, c the
    // measured cost per branch; within [min_budget, max_branches]. fixed_budget >= 1 replaces it.
    float budget_factor = 2.f, min_budget = 2.f, fixed_budget = 0.f;
    int max_branches = 64;
    // The prior samples k of the learned pixel estimate (ContinuationSnapshot::pixel_estimate).
    double pixel_prior = 4.0;
};

// The frozen statistics a pass decides with (docs/theory.md §9.8).
class ContinuationSnapshot {
  public:
    ContinuationSnapshot() = default;  // nothing learned: every decision falls back
    // `unsplit_cost`: C_0, the cost per camera sample of the first pass (0: not known yet).
    static ContinuationSnapshot from(const ContinuationStatistics& stats, const PixelMoments& pixels,
                                     const EarsSettings& settings, double unsplit_cost);
    // The pixel estimate the decisions compare with: the field's I of pixel `pixel` (-1: outside the
    // film, I itself) corrected by the passes so far (learn_pixels).
    float pixel_estimate(long pixel, float I) const {
        return pixel >= 0 && size_t(pixel) < pixel_correction_.size() ? I * pixel_correction_[size_t(pixel)] : I;
    }
    // The efficiency-aware factor q (before clamping and the branch bounds) of a path of relative
    // weight `relative_weight` (its weight over the pixel estimate I) at a continuation of `stage` in
    // `cell` and bin `bin`; < 0 where the statistics are too few.
    float factor(ContinuationStage stage, size_t cell, int bin, float relative_weight) const;
    // A camera sample's branch allowance (walk_policy.h's branch_budget).
    float branch_budget() const { return budget_; }
    size_t learned_points() const { return learned_; }
    // Of learned_points(), those of the surface stage.
    size_t learned_surface_points() const { return learned_surface_; }
    double image_variance() const { return image_variance_; }
    double image_cost() const { return image_cost_; }

  private:
    void learn_pixels(const PixelMoments& pixels, double prior);
    struct Cell {
        float r = -1.f;  // sqrt(M2 / C): the roulette's root ( < 0: too few samples)
        float s = 0.f;   // sqrt(Var / C): the splitting's
    };
    size_t cells_ = 0;
    std::vector<Cell> table_;
    float image_factor_ = 0.f;  // sqrt(C_image / V_image), 0: unknown
    float budget_ = 1.f;
    std::vector<float> pixel_correction_;  // per pixel: I' / I
    size_t learned_ = 0, learned_surface_ = 0;
    double image_variance_ = -1.0, image_cost_ = 0.0;
};

}  // namespace volguide
