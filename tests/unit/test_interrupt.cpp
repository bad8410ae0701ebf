// The CLI's stop signals (apps/volguide/interrupt): the first SIGINT or SIGTERM only raises the flag
// the render loop polls (the completed passes are then written); a second one ends the process at
// once, by the signal's default action. raise() delivers synchronously, so each step is deterministic
// (sending two signals to a running render races with its exit).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include "interrupt.h"

using volguide::cli::InterruptGuard;

namespace {

// Runs `body` in a child process and returns its wait status.
template <typename F>
int in_child(F&& body) {
    const pid_t pid = fork();
    if (pid == 0) {
        body();
        _exit(0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return status;
}

}  // namespace

class InterruptSignals : public testing::TestWithParam<int> {};

TEST_P(InterruptSignals, FirstSignalRaisesTheFlag) {
    const int sig = GetParam();
    const int status = in_child([sig] {
        InterruptGuard guard;
        if (guard.interrupted()) _exit(2);
        std::raise(sig);
        _exit(guard.interrupted() ? 0 : 3);
    });
    ASSERT_TRUE(WIFEXITED(status)) << "the first signal killed the process";
    EXPECT_EQ(WEXITSTATUS(status), 0);
}

TEST_P(InterruptSignals, SecondSignalEndsAtOnce) {
    const int sig = GetParam();
    const int status = in_child([sig] {
        InterruptGuard guard;
        std::raise(sig);
        std::raise(sig);
        _exit(4);  // reached only if the second signal was caught too
    });
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit status " << WEXITSTATUS(status);
    EXPECT_EQ(WTERMSIG(status), sig);
}

TEST_P(InterruptSignals, GuardRestoresThePreviousHandler) {
    const int sig = GetParam();
    const int status = in_child([sig] {
        std::signal(sig, SIG_IGN);
        { InterruptGuard guard; }
        std::raise(sig);  // ignored again once the guard is gone
        _exit(0);
    });
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0);
}

INSTANTIATE_TEST_SUITE_P(Cli, InterruptSignals, testing::Values(SIGINT, SIGTERM),
                         [](const testing::TestParamInfo<int>& info) {
                             return std::string(info.param == SIGINT ? "SIGINT" : "SIGTERM");
                         });
