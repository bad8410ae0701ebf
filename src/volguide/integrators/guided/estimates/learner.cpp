#include "volguide/integrators/guided/estimates/learner.h"

namespace volguide {

Learner::Learner(size_t cells, int width, int height)
    : pixels_(width, height), threads_(cells, &pixels_), total_(cells) {}

void Learner::end_pass() {
    for (Thread& t : threads_) {
        total_ += t.stats;
        t.stats.clear();
    }
}

}  // namespace volguide
