#include "volguide/guiding/roulette_splitting.h"

#include <algorithm>
#include <cmath>

namespace volguide {

float weight_window_factor(float r, float s) {
    // Window centre at r = 1, bounds 2/(1+s) and 2s/(1+s): below, RR to the lower bound; above,
    // split to the upper bound (docs/theory.md eq. 9.1). s = 1 collapses it to q = r.
    const float lower = 2.f / (1.f + s), upper = s * lower;
    if (r < lower) return r / lower;
    if (r > upper) return r / upper;
    return 1.f;
}

RouletteSplittingStats& RouletteSplittingStats::operator+=(const RouletteSplittingStats& o) {
    decisions += o.decisions;
    invalid_estimates += o.invalid_estimates;
    kills += o.kills;
    splits += o.splits;
    extra_branches += o.extra_branches;
    cap_limited += o.cap_limited;
    budget_limited += o.budget_limited;
    unlearned += o.unlearned;
    camera_samples += o.camera_samples;
    if (branch_histogram.size() < o.branch_histogram.size()) branch_histogram.resize(o.branch_histogram.size(), 0);
    for (size_t k = 0; k < o.branch_histogram.size(); ++k) branch_histogram[k] += o.branch_histogram[k];
    pixel_estimate_seconds += o.pixel_estimate_seconds;
    return *this;
}

int RouletteSplittingStats::branches_quantile(double fraction) const {
    uint64_t total = 0;
    for (uint64_t c : branch_histogram) total += c;
    if (total == 0) return 0;
    const double need = fraction * double(total);
    uint64_t seen = 0;
    for (size_t k = 0; k < branch_histogram.size(); ++k) {
        seen += branch_histogram[k];
        if (double(seen) >= need) return int(k);
    }
    return int(branch_histogram.size()) - 1;
}

std::vector<std::pair<std::string, double>> RouletteSplittingStats::named() const {
    auto ratio = [](uint64_t a, uint64_t b) { return b ? double(a) / double(b) : 0.0; };
    uint64_t branches = 0;
    int max_branches = 0;
    for (size_t k = 0; k < branch_histogram.size(); ++k) {
        branches += branch_histogram[k] * k;
        if (branch_histogram[k] > 0) max_branches = int(k);
    }
    return {{"rrs_decisions", double(decisions)},
            {"rrs_invalid_estimate_fraction", ratio(invalid_estimates, decisions)},
            {"rrs_kills", double(kills)},
            {"rrs_splits", double(splits)},
            {"rrs_extra_branches", double(extra_branches)},
            {"rrs_cap_limited", double(cap_limited)},
            {"rrs_budget_limited", double(budget_limited)},
            {"rrs_unlearned", double(unlearned)},
            {"rrs_branches_per_camera_sample", ratio(branches, camera_samples)},
            {"rrs_branches_p999", double(branches_quantile(0.999))},
            {"rrs_branches_max", double(max_branches)},
            // camera samples that reached the cap (the histogram's last bin)
            {"rrs_cap_hits", branch_histogram.empty() ? 0.0 : double(branch_histogram.back())},
            {"rrs_pixel_estimate_seconds", pixel_estimate_seconds},
            {"rrs_branch_budget", double(branch_budget)},
            {"rrs_branch_budget_max", double(largest_branch_budget)}};
}

RouletteSplitting::RouletteSplitting(const RouletteSplittingSettings& settings)
    : settings_(settings), largest_budget_(initial_allowance()) {}

float RouletteSplitting::factor(const Color3& weight, const Color3& estimate, float pixel, int branches,
                                float allowance) const {
    RouletteSplittingStats& st = stats_.local();
    ++st.decisions;
    const float expected = (weight * estimate).average();
    if (!(expected > 0.f) || !std::isfinite(expected) || !(pixel > 0.f)) {
        ++st.invalid_estimates;
        return 1.f;
    }
    return bounded(weight_window_factor(expected / pixel, settings_.window), branches, allowance, st);
}

float RouletteSplitting::bound(float q, int branches, float allowance) const {
    RouletteSplittingStats& st = stats_.local();
    ++st.decisions;
    return bounded(q, branches, allowance, st);
}

void RouletteSplitting::set_cost_ratio(float ratio) {
    adaptive_budget_ = ratio > 0.f && std::isfinite(ratio)
                           ? std::clamp(std::floor(kBudgetFactor * ratio), kMinBudget, float(settings_.max_branches))
                           : kDefaultBudget;
    largest_budget_ = std::max(largest_budget_, initial_allowance());
}

void RouletteSplitting::count_unlearned() const { ++stats_.local().unlearned; }

float RouletteSplitting::bounded(float q, int branches, float allowance, RouletteSplittingStats& st) const {
    q = std::clamp(q, settings_.q_min, splits() ? settings_.q_max : 1.f);
    // n = floor(q + xi) <= ceil(q) <= floor(allowance): every copy keeps an allowance >= 1. First: every
    // other branch made so far held an allowance >= 1 of the same budget B <= max_branches, so after it
    // the cap below never binds (cap_limited counts only what the budget left to the cap).
    const float budget = std::max(1.f, std::floor(allowance));
    if (q > budget) {
        q = budget;
        ++st.budget_limited;
    }
    // The continuations may not take the camera sample past its branch cap: n <= floor(q) + 1 and
    // this branch is one of them, so q <= max_branches - branches + 1 bounds n.
    const float allowed = float(std::max(1, settings_.max_branches - branches + 1));
    if (q > allowed) {
        q = allowed;
        ++st.cap_limited;
    }
    return q;
}

void RouletteSplitting::count_outcome(int n) const {
    RouletteSplittingStats& st = stats_.local();
    if (n == 0) ++st.kills;
    if (n > 1) {
        ++st.splits;
        st.extra_branches += uint64_t(n - 1);
    }
}

void RouletteSplitting::count_camera_sample(int branches) const {
    RouletteSplittingStats& st = stats_.local();
    ++st.camera_samples;
    if (st.branch_histogram.empty()) st.branch_histogram.assign(size_t(settings_.max_branches) + 1, 0);
    st.branch_histogram[size_t(std::clamp(branches, 0, settings_.max_branches))] += 1;
}

RouletteSplittingStats RouletteSplitting::stats() const {
    RouletteSplittingStats total;
    for (const RouletteSplittingStats& s : stats_) total += s;
    total.pixel_estimate_seconds = pixel_estimate_seconds_;
    // ears decides with its own budget (continuation_snapshot.h: ears_branch_budget).
    total.branch_budget = settings_.mode == RouletteMode::Ears ? 0.f : initial_allowance();
    total.largest_branch_budget = settings_.mode == RouletteMode::Ears ? 0.f : std::max(largest_budget_, initial_allowance());
    return total;
}

}  // namespace volguide
