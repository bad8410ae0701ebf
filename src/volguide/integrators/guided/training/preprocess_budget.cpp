#include "volguide/integrators/guided/training/preprocess_budget.h"

#include <algorithm>

namespace volguide {

namespace {
constexpr double kMinStepSeconds = 1e-3;
}

PreprocessBudget::PreprocessBudget(double time_budget, double fraction)
    : total_(time_budget > 0 ? std::max(0.0, time_budget * fraction) : 0.0), start_(Clock::now()) {}

double PreprocessBudget::elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

double PreprocessBudget::remaining() const { return limited() ? std::max(0.0, total_ - elapsed()) : 0.0; }

double PreprocessBudget::limit(double share) const {
    if (!limited()) return 0.0;
    return std::max(kMinStepSeconds, share * remaining());
}

double PreprocessBudget::limit_within(double share, double fraction) const {
    if (!limited()) return 0.0;
    return std::max(kMinStepSeconds, std::min(share * remaining(), fraction * total_ - elapsed()));
}

bool PreprocessBudget::over(double step_limit, double step_elapsed, double round_seconds) {
    return step_limit > 0 && step_elapsed + round_seconds > step_limit;
}

}  // namespace volguide
