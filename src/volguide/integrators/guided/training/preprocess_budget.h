#pragma once
// guided_volpath's pre-pass deadline (issue 55): everything before the first image pass (photons, the
// pixel estimate, the selection pilot, the method choice's probes) takes at most training_fraction of a
// --time budget, whatever the resolution. One deadline for the whole pre-pass; each step is given a share
// of what remains when it starts (limit()), so a step that ends early leaves its time to the next ones and
// the steps' limits never sum past the deadline. Without a time budget there is no deadline: every limit
// is 0 (none) and nothing depends on the wall clock.
#include <chrono>

namespace volguide {

class PreprocessBudget {
public:
    // `time_budget` 0: none; `fraction`: the pre-pass's share of it.
    PreprocessBudget(double time_budget, double fraction);
    bool limited() const { return total_ > 0; }
    double total() const { return total_; }  // the pre-pass's seconds (0: none)
    double elapsed() const;
    // Seconds left before the deadline (0 once past it; 0 without a budget).
    double remaining() const;
    // A step's limit: `share` of what remains, at least a millisecond (0 without a budget: none).
    double limit(double share) const;
    // The same, capped so that the pre-pass so far plus the step stays within `fraction` of the total
    // (the cheap first stage's own ceiling).
    double limit_within(double share, double fraction) const;
    // Whether a step that started `step_elapsed` seconds ago with limit `step_limit` should stop before
    // another round that takes about `round_seconds` (false without a budget).
    static bool over(double step_limit, double step_elapsed, double round_seconds);

private:
    using Clock = std::chrono::steady_clock;
    double total_ = 0;
    Clock::time_point start_;
};

}  // namespace volguide
