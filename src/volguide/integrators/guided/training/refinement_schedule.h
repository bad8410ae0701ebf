#pragma once
// When guided_volpath refines its field during the render (issue 39, docs/theory.md §22.4): at doublings
// of the samples per pixel, for as long as the last refinement paid.
//
// Each refinement (a further photon pass added to the field, field_refinement.h) is judged by the
// stretch of passes rendered with its field against the stretch before it: their per-sample noise
// (PassReport::relative_variance, weighted by the passes' samples) times, under a time budget, their
// seconds per sample per pixel: the inefficiency whose inverse is what equal-time rendering gains.
//   - The first refinement comes at `first_spp` (the initial field's stretch then holds passes of
//     2, 4, 8, ... spp) if the budget leaves at least kFirstRefinementCover times the initial
//     training's seconds.
//   - A later one comes at the next doubling if the last lowered the inefficiency by at least `gain`
//     (fraction), fewer than `passes` were made and, under a budget, the remaining time times that
//     gain exceeds twice the last refinement's seconds (the next adds twice the photons).
//   - Otherwise refining stops, and a last refinement that made the stretch worse (by more than twice
//     the ratio's standard error, from the passes' own: the noise of heavy-tailed pixels is itself
//     noisy) is undone.
// Without a time budget only the noise is compared (a pure function of the samples: the same
// schedule, the same image, for any thread count).
#include <string>
#include <utility>
#include <vector>

#include "volguide/integrators/integrator.h"

namespace volguide {

struct RefinementScheduleSettings {
    int passes = 0;        // refinements at most (0: none)
    int first_spp = 16;    // the first one at this many samples per pixel, the next ones at doublings
    double gain = 0.05;    // a refinement that lowered the inefficiency by less than this ends refining
};

enum class RefinementAction { Continue, Refine, Revert };

// Why refining ended (RefinementSchedule::named: refine_stop_reason).
enum class RefinementStop { Running = 0, NoGain = 1, Worse = 2, PassLimit = 3, Budget = 4 };

class RefinementSchedule {
  public:
    // `time_budget` 0: none. `training_seconds`: the initial training's (the first refinement's guard).
    RefinementSchedule(const RefinementScheduleSettings& settings, double time_budget, double training_seconds);
    // Called after every pass; says what the integrator does before the next one.
    RefinementAction on_pass(const PassReport& pass);
    // The refinement asked for (Refine or Revert) was made in `seconds`.
    void done(double seconds);
    int refinements() const { return refinements_; }
    // refine_* figures for --stats: the count, their seconds, each stretch's inefficiency and samples
    // per pixel, where and why refining stopped.
    std::vector<std::pair<std::string, double>> named() const;

    static constexpr double kFirstRefinementCover = 4.0;

  private:
    // Passes rendered with one field.
    struct Stretch {
        double spp = 0, seconds = 0;
        double noise_spp = 0, noise_weight = 0;  // sum of relative_variance x spp over passes that have it
        double error_sq = 0;                     // sum of (relative_variance_error x spp)^2 over them
        void add(const PassReport& pass);
        bool measured() const { return noise_weight > 0; }
        double inefficiency(bool timed) const;
        double relative_error() const;  // of the noise (and so of the inefficiency)
    };
    RefinementAction stop(RefinementStop why, int spp);

    RefinementScheduleSettings settings_;
    double budget_, training_seconds_;
    Stretch current_, previous_;
    int next_spp_;
    int refinements_ = 0;
    double seconds_ = 0, last_seconds_ = 0;
    RefinementStop stopped_ = RefinementStop::Running;
    int stop_spp_ = 0;
    std::vector<std::pair<double, double>> stretches_;  // (spp, inefficiency) of each judged stretch
};

}  // namespace volguide
