#include "volguide/integrators/guided/walk/walk_stats.h"

namespace volguide {

WalkGuideStats& WalkGuideStats::operator+=(const WalkGuideStats& o) {
#define VOLGUIDE_WALK_GUIDE_ADD(member, name, of) member += o.member;
    VOLGUIDE_WALK_GUIDE_COUNTERS(VOLGUIDE_WALK_GUIDE_ADD)
#undef VOLGUIDE_WALK_GUIDE_ADD
    return *this;
}

std::vector<std::pair<std::string, double>> WalkGuideStats::named() const {
    auto ratio = [](uint64_t a, uint64_t b) { return b ? double(a) / double(b) : 0.0; };
#define VOLGUIDE_WALK_GUIDE_NAMED(member, name, of) {name, ratio(member, uint64_t(of))},
    return {VOLGUIDE_WALK_GUIDE_COUNTERS(VOLGUIDE_WALK_GUIDE_NAMED)};
#undef VOLGUIDE_WALK_GUIDE_NAMED
}

WalkGuideStats WalkStatsTally::total() const {
    WalkGuideStats total;
    for (const WalkGuideStats& s : per_thread_) total += s;
    return total;
}

}  // namespace volguide
