#include "interrupt.h"

#include <csignal>

namespace volguide::cli {

namespace {
std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");
using Handler = void (*)(int);
Handler g_previous_int = SIG_DFL, g_previous_term = SIG_DFL;

extern "C" void on_stop_signal(int signal) {
    g_interrupted.store(true);
    std::signal(signal, SIG_DFL);  // a second Ctrl-C (or SIGTERM) ends the process
}

Handler install(int signal) {
    Handler previous = std::signal(signal, on_stop_signal);
    if (previous == SIG_ERR) previous = SIG_DFL;
    // A process started with the signal ignored (SIGINT in a background job of a script) keeps ignoring it.
    if (previous == SIG_IGN) std::signal(signal, SIG_IGN);
    return previous;
}
}  // namespace

InterruptGuard::InterruptGuard() {
    g_interrupted = false;
    g_previous_int = install(SIGINT);
    g_previous_term = install(SIGTERM);
}

InterruptGuard::~InterruptGuard() {
    std::signal(SIGINT, g_previous_int);
    std::signal(SIGTERM, g_previous_term);
}

const std::atomic<bool>* InterruptGuard::flag() const {
    return &g_interrupted;
}

bool InterruptGuard::interrupted() const {
    return g_interrupted.load();
}

}  // namespace volguide::cli
