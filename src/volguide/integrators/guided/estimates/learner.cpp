#include "volguide/integrators/guided/estimates/learner.h"

#include <stdexcept>
#include <utility>

namespace volguide {

Learner::Learner(size_t cells, int width, int height, const CostModel& costs)
    : pixels_(width, height), pixels_total_(width, height), threads_(cells, &pixels_, &costs), total_(cells) {}

void Learner::end_pass() {
    for (Thread& t : threads_) {
        total_ += t.stats;
        t.stats.clear();
    }
    pixels_total_ += pixels_;
    pixels_.clear();
}

void Learner::set_total(CellStatistics total) {
    if (total.cells() != total_.cells())
        throw std::runtime_error("the allocation's statistics are of another field (a different cell count)");
    total_ = std::move(total);
}

}  // namespace volguide
