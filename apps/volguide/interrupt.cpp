#include "interrupt.h"

#include <csignal>

namespace volguide::cli {

namespace {
std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");
using Handler = void (*)(int);
Handler g_previous = SIG_DFL;

extern "C" void on_sigint(int) {
    g_interrupted.store(true);
    std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process
}
}  // namespace

InterruptGuard::InterruptGuard() {
    g_interrupted = false;
    g_previous = std::signal(SIGINT, on_sigint);
    if (g_previous == SIG_ERR) g_previous = SIG_DFL;
    // A process started with SIGINT ignored (a background job of a script) keeps ignoring it.
    if (g_previous == SIG_IGN) std::signal(SIGINT, SIG_IGN);
}

InterruptGuard::~InterruptGuard() {
    std::signal(SIGINT, g_previous);
}

const std::atomic<bool>* InterruptGuard::flag() const {
    return &g_interrupted;
}

bool InterruptGuard::interrupted() const {
    return g_interrupted.load();
}

}  // namespace volguide::cli
