#pragma once
// Draws render progress on stderr: a bar with ETA redrawn in place on a terminal, a plain line
// every few seconds otherwise (logs, CI), nothing when quiet.
#include <chrono>
#include <string>

#include "volguide/core/progress.h"

namespace volguide::cli {

class ProgressDisplay {
  public:
    explicit ProgressDisplay(bool quiet);
    void update(const Progress& p);
    // Ends the bar's line (call once rendering is over).
    void finish();

  private:
    bool quiet_, tty_;
    bool drawn_ = false;
    std::string last_phase_;
    std::chrono::steady_clock::time_point last_line_{};
};

std::string format_seconds(double s);

}  // namespace volguide::cli
