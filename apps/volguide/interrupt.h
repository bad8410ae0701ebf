#pragma once
// Ctrl-C or SIGTERM (what Slurm and other schedulers send at a time limit or preemption) during a
// render: the first one asks the render loop to stop after the current pass (the completed passes
// are written, with their actual sample range); a second one terminates at once.
#include <atomic>

namespace volguide::cli {

class InterruptGuard {
  public:
    InterruptGuard();   // installs the handler
    ~InterruptGuard();  // restores the previous one
    const std::atomic<bool>* flag() const;
    bool interrupted() const;
};

}  // namespace volguide::cli
