// A full or unwritable output (issue 24): the render exits 1 with a message naming the file and
// leaves nothing behind, neither the output nor a temporary file. "Full" is a file-size limit
// (RLIMIT_FSIZE, SIGXFSZ ignored), which fails writes with EFBIG exactly as a full disk fails them
// with ENOSPC, without needing a small file system or root.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>

#include "support/cli.h"
#include "support/test_support.h"

using namespace volguide::test;
namespace fs = std::filesystem;

namespace {

const char* kFullDiskScene = R"(<scene version="3.0.0">
    <sensor type="perspective">
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="64"/></film>
        <sampler type="independent"><integer name="sample_count" value="1"/></sampler>
    </sensor>
    <shape type="sphere"><bsdf type="diffuse"/></shape>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
</scene>
)";

struct LimitedRun {
    int exit_code = -1;
    std::string err;
};

// volguide ARGS in `dir`, with files limited to `max_bytes`.
LimitedRun run_with_file_limit(const fs::path& dir, rlim_t max_bytes, const std::vector<std::string>& args) {
    const pid_t pid = fork();
    if (pid == 0) {
        if (chdir(dir.c_str()) != 0 || !freopen("stderr.txt", "w", stderr)) _exit(99);
        std::signal(SIGXFSZ, SIG_IGN);  // a write past the limit then fails instead of killing
        const rlimit limit{max_bytes, max_bytes};
        if (setrlimit(RLIMIT_FSIZE, &limit) != 0) _exit(97);
        const std::string cli = cli_path();
        std::vector<char*> argv{const_cast<char*>(cli.c_str())};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execv(cli.c_str(), argv.data());
        _exit(98);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    LimitedRun r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.err = read_file((dir / "stderr.txt").string());
    return r;
}

// Everything in `dir` but the scene and the captured stderr.
std::vector<std::string> leftovers(const fs::path& dir) {
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        if (name != "s.xml" && name != "stderr.txt") files.push_back(name);
    }
    return files;
}

}  // namespace

class FullOutput : public testing::TestWithParam<std::vector<std::string>> {};

TEST_P(FullOutput, ExitsOneAndLeavesNothingBehind) {
    TempDir dir("full-disk");
    dir.write("s.xml", kFullDiskScene);
    // 2 KiB: the scene (a few hundred bytes) is read, not written; every output is larger.
    std::vector<std::string> args = {"render", "s.xml", "--quiet", "--threads", "1"};
    for (const std::string& a : GetParam()) args.push_back(a);
    const LimitedRun r = run_with_file_limit(dir.path(), 2048, args);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("volguide: "), std::string::npos) << r.err;
    EXPECT_EQ(leftovers(dir.path()), std::vector<std::string>{}) << r.err;
    // Without the limit the same command succeeds: the failure above is the full disk's.
    const LimitedRun ok = run_with_file_limit(dir.path(), RLIM_INFINITY, args);
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_FALSE(leftovers(dir.path()).empty());
}

INSTANTIATE_TEST_SUITE_P(Cli, FullOutput,
                         testing::Values(std::vector<std::string>{"-o", "out.exr"},
                                         std::vector<std::string>{"-o", "out.png"},
                                         std::vector<std::string>{"-o", "out.exr", "--variance"}),
                         [](const testing::TestParamInfo<std::vector<std::string>>& info) {
                             return std::to_string(info.index);
                         });

// /dev/full as the output: refused before rendering (it does not name an .exr or .png), exit 2 as
// every usage error, and /dev is left as it was.
TEST(FullOutputDevice, DevFullIsAUsageError) {
    TempDir dir("dev-full");
    const std::string scene = dir.write("s.xml", kFullDiskScene);
    const CliResult r = run_cli({"render", scene, "--quiet", "-o", "/dev/full"});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("/dev/full"), std::string::npos) << r.err;
    for (const auto& e : fs::directory_iterator("/dev"))
        EXPECT_EQ(e.path().filename().string().find("full.tmp"), std::string::npos) << e.path();
}
