#pragma once
// Ctrl-C during a render: the first SIGINT asks the render loop to stop after the current pass
// (the completed passes are written); a second one terminates at once.
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
