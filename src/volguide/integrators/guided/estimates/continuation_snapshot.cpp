#include "volguide/integrators/guided/estimates/continuation_snapshot.h"

#include <algorithm>
#include <cmath>

namespace volguide {

ContinuationSnapshot ContinuationSnapshot::from(const CellStatistics& stats, const PixelMoments& pixels,
                                                const EarsSettings& settings, double unsplit_cost) {
    ContinuationSnapshot snap;
    snap.cells_ = stats.cells();
    snap.table_.resize(size_t(kContinuationStages) * snap.cells_ * size_t(kContinuationDirectionBins));
    for (int stage = 0; stage < kContinuationStages; ++stage)
        for (size_t cell = 0; cell < snap.cells_; ++cell)
            for (int bin = 0; bin < kContinuationDirectionBins; ++bin) {
                const ContinuationMoments& m = stats.continuation(ContinuationStage(stage), cell, bin);
                if (m.n < std::max<uint64_t>(settings.min_samples, 2) || !(m.cost.value() > 0.0)) continue;
                const double n = double(m.n), mean = m.sum.value() / n, m2 = std::max(0.0, m.sum_sq.value() / n);
                const double cost = m.cost.value() / n;
                Cell& c = snap.table_[(size_t(stage) * snap.cells_ + cell) * size_t(kContinuationDirectionBins) +
                                      size_t(bin)];
                c.r = float(std::sqrt(m2 / cost));
                c.s = float(std::sqrt(std::max(0.0, m2 - mean * mean) / cost));
                ++snap.learned_;
                snap.learned_surface_ += ContinuationStage(stage) == ContinuationStage::Surface;
            }
    const uint64_t samples = stats.camera_samples();
    snap.image_cost_ = samples ? double(stats.cost()) / double(samples) : 0.0;
    snap.learn_pixels(pixels, settings.pixel_prior);
    if (snap.image_variance_ > 0.0 && snap.image_cost_ > 0.0)
        snap.image_factor_ = float(std::sqrt(snap.image_cost_ / snap.image_variance_));
    // Cost budget -> branches: the mean cost of a branch measured so far (splits late in a path make
    // cheaper branches, so more of them fit).
    const double per_branch = stats.branches() ? double(stats.cost()) / double(stats.branches()) : 0.0;
    double budget = settings.min_budget;
    if (settings.fixed_budget >= 1.f)
        budget = settings.fixed_budget;
    else if (unsplit_cost > 0.0 && per_branch > 0.0)
        budget = std::max(budget, double(settings.budget_factor) * unsplit_cost / per_branch);
    snap.budget_ = float(std::min(std::floor(budget), double(settings.max_branches)));
    return snap;
}

// The learned estimate I' = I c of each pixel: c = (k + sum x) / (k + n), the mean of x = X / I shrunk
// towards 1 (I itself) by k prior samples; and the image's relative variance per sample, the mean over
// the pixels with n >= 2 of var(x) / c^2 = var(X) / I'^2. Relative to I alone, pixels whose I is far too
// dark (x ~ 100 where the field misses light diffused through a dense medium) dominated V.
void ContinuationSnapshot::learn_pixels(const PixelMoments& pixels, double prior) {
    const size_t count = size_t(pixels.width()) * size_t(pixels.height());
    pixel_correction_.assign(count, 1.f);
    double total = 0.0;
    size_t used = 0;
    for (size_t p = 0; p < count; ++p) {
        const PixelMoments::Pixel px = pixels.at(p);
        const float c = px.correction(prior);
        pixel_correction_[p] = c;
        if (px.n < 2.0 || !(c > 0.f)) continue;
        const double var = std::max(0.0, (px.sum_sq - px.sum * px.sum / px.n) / (px.n - 1.0));
        total += var / (double(c) * double(c));
        ++used;
    }
    image_variance_ = used > 0 ? total / double(used) : -1.0;
}

float ContinuationSnapshot::factor(ContinuationStage stage, size_t cell, int bin, float relative_weight) const {
    if (cell >= cells_ || !(image_factor_ > 0.f) || !(relative_weight >= 0.f) || !std::isfinite(relative_weight))
        return -1.f;
    const Cell& c = table_[(size_t(stage) * cells_ + cell) * size_t(kContinuationDirectionBins) + size_t(bin)];
    if (c.r < 0.f) return -1.f;
    // Roulette by the second moment (what RR adds to the variance is (1/q - 1) M2); splitting by the
    // variance (what n copies take from it is (1 - 1/n) Var), and only where both ask for it.
    const float q_r = relative_weight * c.r * image_factor_;
    if (q_r <= 1.f) return q_r;
    const float q_s = relative_weight * c.s * image_factor_;
    return q_s >= 1.f ? q_s : 1.f;
}

ContinuationLearning::ContinuationLearning(size_t cells, int width, int height, const EarsSettings& settings,
                                           const CostModel& costs)
    : settings_(settings), learner_(cells, width, height, costs) {
    snapshot_ = ContinuationSnapshot::from(learner_.total(), learner_.pixels(), settings_, 0.0);
}

void ContinuationLearning::end_pass() {
    learner_.end_pass();
    const CellStatistics& total = learner_.total();
    // The first pass decided nothing (no statistics yet): its cost is the unsplit walk's.
    if (updates_ == 0 && total.camera_samples() > 0)
        unsplit_cost_ = double(total.cost()) / double(total.camera_samples());
    snapshot_ = ContinuationSnapshot::from(total, learner_.pixels(), settings_, unsplit_cost_);
    ++updates_;
}

std::vector<std::pair<std::string, double>> ContinuationLearning::named() const {
    return {{"ears_updates", double(updates_)},
            {"ears_learned_points", double(snapshot_.learned_points())},
            {"ears_learned_surface_points", double(snapshot_.learned_surface_points())},
            {"ears_image_relative_variance", snapshot_.image_variance()},
            {"ears_image_cost_per_sample", snapshot_.image_cost()},
            {"ears_branch_budget", double(snapshot_.branch_budget())},
            {"ears_unsplit_cost_per_sample", unsplit_cost_},
            {"ears_recorded_camera_samples", double(learner_.total().camera_samples())}};
}

}  // namespace volguide
