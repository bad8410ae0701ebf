#pragma once
// What efficiency-aware RR and splitting (rrs=ears, docs/theory.md §9.8) decides with: the learner's
// statistics of the render's own passes (learner.h, cell_statistics.h) — per leaf of the guiding field x
// direction bin x continuation stage, the moments of what a vertex's continuation collected per unit
// path weight and its cost (the cost model's); per camera sample its cost and branches, per pixel the
// moments of the relative sample X / I (I: the pixel estimate), whence the image's relative variance V
// and cost C per sample — frozen between passes into a ContinuationSnapshot. The decisions of a pass
// read the snapshot, never the sums being filled: within a pass every q is a fixed function of the
// path, so every decision stays unbiased (§9.4) whatever the statistics are, and the statistics' sums
// being exact, the image is the same for any thread count.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "volguide/integrators/guided/estimates/cell_statistics.h"
#include "volguide/integrators/guided/estimates/learner.h"
#include "volguide/integrators/volpath/walk_policy.h"

namespace volguide {

struct EarsSettings {
    // Continuations a (stage, cell, bin) needs before its moments are used; fewer: the fallback.
    uint64_t min_samples = 32;
    // The adaptive branch budget: a camera sample may cost about budget_factor x what an unsplit one
    // cost (the first pass, made before any statistics), in branches B = budget_factor x C_0 / c, c the
    // measured cost per branch; within [min_budget, max_branches]. fixed_budget >= 1 replaces it.
    float budget_factor = 2.f, min_budget = 2.f, fixed_budget = 0.f;
    int max_branches = 16;
    // The prior samples k of the learned pixel estimate (ContinuationSnapshot::pixel_estimate).
    double pixel_prior = 4.0;
};

// The frozen statistics a pass decides with (docs/theory.md §9.8).
class ContinuationSnapshot {
  public:
    ContinuationSnapshot() = default;  // nothing learned: every decision falls back
    // `unsplit_cost`: C_0, the cost per camera sample of the first pass (0: not known yet).
    static ContinuationSnapshot from(const CellStatistics& stats, const PixelMoments& pixels,
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

// rrs=ears's learning over a render: the learner over the render's passes and the snapshot the current
// pass decides with. end_pass() (between passes) adds the pass to the learner and freezes the next
// snapshot.
class ContinuationLearning {
  public:
    // `cells`: the field's leaves + 1; the film's width and height; the recorders' cost model (must
    // outlive the object).
    ContinuationLearning(size_t cells, int width, int height, const EarsSettings& settings, const CostModel& costs);
    const ContinuationSnapshot& snapshot() const { return snapshot_; }
    // The calling thread's recorder (one camera sample at a time: begin ... end).
    CellRecorder& recorder() const { return learner_.recorder(); }
    long pixel(Point2f film_uv) const { return learner_.pixel(film_uv); }
    void end_pass();
    // The snapshot's figures for --stats.
    std::vector<std::pair<std::string, double>> named() const;

  private:
    EarsSettings settings_;
    Learner learner_;
    ContinuationSnapshot snapshot_;
    double unsplit_cost_ = 0.0;  // C_0: the first pass's cost per camera sample
    int updates_ = 0;
};

}  // namespace volguide
