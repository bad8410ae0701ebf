#pragma once
// The process's CPU time: what a cost is measured in on a machine that is not idle (every thread's time
// while it ran, not the wall clock's).
#include <time.h>

namespace volguide {

inline double process_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace volguide
