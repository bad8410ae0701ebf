#include "volguide/integrators/guided/training/refinement_schedule.h"

#include <cmath>
#include <fmt/format.h>

namespace volguide {

void RefinementSchedule::Stretch::add(const PassReport& pass) {
    spp += pass.spp;
    seconds += pass.pass_seconds;
    if (std::isfinite(pass.relative_variance)) {
        noise_spp += pass.relative_variance * pass.spp;
        noise_weight += pass.spp;
        const double e = std::isfinite(pass.relative_variance_error) ? pass.relative_variance_error * pass.spp : 0.0;
        error_sq += e * e;
    }
}

double RefinementSchedule::Stretch::relative_error() const {
    const double noise = noise_spp / noise_weight;
    return noise > 0 ? std::sqrt(error_sq) / noise_weight / noise : 0.0;
}

double RefinementSchedule::Stretch::inefficiency(bool timed) const {
    const double noise = noise_spp / noise_weight;
    return timed ? noise * seconds / spp : noise;
}

RefinementSchedule::RefinementSchedule(const RefinementScheduleSettings& settings, double time_budget,
                                       double training_seconds)
    : settings_(settings), budget_(time_budget), training_seconds_(training_seconds), next_spp_(settings.first_spp) {
    if (settings_.passes <= 0) stopped_ = RefinementStop::PassLimit;
}

RefinementAction RefinementSchedule::stop(RefinementStop why, int spp) {
    stopped_ = why;
    stop_spp_ = spp;
    return why == RefinementStop::Worse ? RefinementAction::Revert : RefinementAction::Continue;
}

RefinementAction RefinementSchedule::on_pass(const PassReport& pass) {
    if (stopped_ != RefinementStop::Running) return RefinementAction::Continue;
    current_.add(pass);
    if (pass.spp_done < next_spp_ || !current_.measured()) return RefinementAction::Continue;
    next_spp_ = 2 * pass.spp_done;
    const bool timed = budget_ > 0;
    const double remaining = budget_ - pass.seconds;
    const double now = current_.inefficiency(timed);
    if (refinements_ == 0) {
        if (timed && remaining < kFirstRefinementCover * training_seconds_) return stop(RefinementStop::Budget, pass.spp_done);
    } else {
        const double ratio = now / previous_.inefficiency(timed);
        const double ratio_error = ratio * std::hypot(current_.relative_error(), previous_.relative_error());
        stretches_.emplace_back(current_.spp, now);
        if (ratio > 1.0 + 2.0 * ratio_error) return stop(RefinementStop::Worse, pass.spp_done);
        if (ratio > 1.0 - settings_.gain) return stop(RefinementStop::NoGain, pass.spp_done);
        if (refinements_ >= settings_.passes) return stop(RefinementStop::PassLimit, pass.spp_done);
        if (timed && remaining * (1.0 - ratio) < 2.0 * last_seconds_) return stop(RefinementStop::Budget, pass.spp_done);
    }
    if (refinements_ == 0) stretches_.emplace_back(current_.spp, now);
    previous_ = current_;
    current_ = Stretch{};
    return RefinementAction::Refine;
}

void RefinementSchedule::done(double seconds) {
    if (stopped_ == RefinementStop::Running) ++refinements_;
    seconds_ += seconds;
    last_seconds_ = seconds;
}

std::vector<std::pair<std::string, double>> RefinementSchedule::named() const {
    std::vector<std::pair<std::string, double>> out = {{"refine_passes", double(refinements_)},
                                                       {"refine_seconds", seconds_},
                                                       {"refine_stop_reason", double(int(stopped_))},
                                                       {"refine_stop_spp", double(stop_spp_)}};
    for (size_t k = 0; k < stretches_.size(); ++k) {
        out.emplace_back(fmt::format("refine_stretch{}_spp", k), stretches_[k].first);
        out.emplace_back(fmt::format("refine_stretch{}_inefficiency", k), stretches_[k].second);
    }
    return out;
}

}  // namespace volguide
