#include "progress_display.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace volguide::cli {

std::string format_seconds(double s) {
    if (!(s >= 0)) return "?";
    if (s < 60) return fmt::format("{:.1f} s", s);
    int total = int(std::lround(s));
    if (total < 3600) return fmt::format("{}m{:02d}s", total / 60, total % 60);
    return fmt::format("{}h{:02d}m", total / 3600, (total / 60) % 60);
}

ProgressDisplay::ProgressDisplay(bool quiet) : quiet_(quiet), tty_(isatty(fileno(stderr)) != 0) {}

namespace {
std::string describe(const Progress& p) {
    std::string spp = p.spp_target > 0 ? fmt::format("{}/{} spp", p.spp_done, p.spp_target)
                                       : fmt::format("{} spp", p.spp_done);
    std::string eta = p.eta >= 0 ? ", ETA " + format_seconds(p.eta) : "";
    return fmt::format("{} {:3.0f}%  {}  {} elapsed{}", p.phase, 100.0 * p.fraction, spp,
                       format_seconds(p.elapsed), eta);
}
}  // namespace

void ProgressDisplay::update(const Progress& p) {
    if (quiet_) return;
    if (tty_) {
        const int width = 30;
        int filled = int(std::lround(p.fraction * width));
        std::string bar(size_t(filled), '#');
        bar.append(size_t(width - filled), '.');
        std::fprintf(stderr, "\r[%s] %s\033[K", bar.c_str(), describe(p).c_str());
        std::fflush(stderr);
        drawn_ = true;
        return;
    }
    // Plain lines: one when a phase starts (an instant "preprocess" with nothing to do is skipped),
    // then one every 5 seconds.
    auto now = std::chrono::steady_clock::now();
    bool phase_change = p.phase != last_phase_;
    if (phase_change && p.phase == "preprocess" && p.fraction == 0) {
        last_phase_ = p.phase;
        return;
    }
    if (!phase_change && now - last_line_ < std::chrono::seconds(5)) return;
    last_line_ = now;
    last_phase_ = p.phase;
    std::fprintf(stderr, "volguide: %s\n", describe(p).c_str());
    std::fflush(stderr);
}

void ProgressDisplay::finish() {
    if (quiet_ || !tty_ || !drawn_) return;
    std::fprintf(stderr, "\n");
    drawn_ = false;
}

}  // namespace volguide::cli
