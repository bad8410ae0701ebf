// `volguide render --checkpoint` / `--resume` end to end (docs/distributed.md, "Checkpoints"): a render
// stopped by SIGTERM after a checkpoint exists, resumed with another thread count, writes the EXR of
// the uninterrupted render byte for byte, for volpath and for guided_volpath with its defaults (the
// stopped render's checkpoint is past the coarse stage's decision, so the full field the render
// trained is in it); a checkpoint of other options or a corrupt one is refused, and nothing is written.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "support/cli.h"
#include "support/test_support.h"
#include "volguide/integrators/checkpoint_file.h"

using namespace volguide::test;

namespace {

// The benchmark's fog box, tiny, with `integrator`.
std::vector<std::string> fogbox_render(const std::string& integrator, const std::string& spp) {
    return {"render", source_dir() + "/bench/scenes/fogbox.xml", "-D", "width=24", "-D", "height=16", "-D",
            "integrator=" + integrator, "--spp", spp, "--seed", "5", "--quiet"};
}

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
    args.insert(args.end(), more.begin(), more.end());
    return args;
}

// The checkpoint's samples per pixel (-1: none readable yet).
int checkpoint_spp(const std::string& path) {
    try {
        return volguide::load_checkpoint(path).state.spp_done;
    } catch (const volguide::CheckpointError&) {
        return -1;
    }
}

// Starts the CLI, sends SIGTERM once `checkpoint` holds at least `min_spp` samples per pixel, and waits
// for it; returns its exit code (-1 when it finished before the signal could interrupt it).
int render_until_checkpoint(const std::vector<std::string>& args, const std::string& checkpoint, int min_spp,
                            const TempDir& dir) {
    const pid_t pid = fork();
    if (pid == 0) {
        std::vector<char*> argv;
        const std::string cli = cli_path();
        argv.push_back(const_cast<char*>(cli.c_str()));
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        freopen(dir.file("bg.out").c_str(), "w", stdout);
        freopen(dir.file("bg.err").c_str(), "w", stderr);
        execv(cli.c_str(), argv.data());
        _exit(127);
    }
    int status = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
    while (checkpoint_spp(checkpoint) < min_spp && std::chrono::steady_clock::now() < deadline) {
        if (waitpid(pid, &status, WNOHANG) == pid) return -1;  // done before it could be interrupted
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    kill(pid, SIGTERM);
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void expect_resume_is_bit_identical(const std::string& integrator, const std::string& spp, int min_spp) {
    TempDir dir("checkpoint-" + integrator);
    const std::vector<std::string> base = fogbox_render(integrator, spp);
    const CliResult whole = run_cli(with(base, {"--threads", "2", "-o", dir.file("whole.exr")}));
    ASSERT_EQ(whole.exit_code, 0) << whole.err;

    const std::string ckpt = dir.file("render.ckpt");
    const int code = render_until_checkpoint(
        with(base, {"--threads", "2", "--checkpoint", ckpt, "--checkpoint-every", "0.001", "-o", dir.file("cut.exr")}),
        ckpt, min_spp, dir);
    ASSERT_EQ(code, 0) << read_file(dir.file("bg.err"));
    EXPECT_NE(read_file(dir.file("bg.out")).find("interrupted"), std::string::npos) << read_file(dir.file("bg.out"));
    const int cut = checkpoint_spp(ckpt);
    ASSERT_GE(cut, min_spp);
    ASSERT_LT(cut, std::stoi(spp)) << "the render was not interrupted";

    const CliResult resumed =
        run_cli(with(base, {"--threads", "1", "--resume", ckpt, "--checkpoint", ckpt, "-o", dir.file("resumed.exr")}));
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    EXPECT_EQ(checkpoint_spp(ckpt), std::stoi(spp));
    const std::string a = read_file(dir.file("whole.exr")), b = read_file(dir.file("resumed.exr"));
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(a == b) << integrator << ": the resumed render (checkpoint at " << cut
                        << " spp) differs from the uninterrupted one";
    // The comparison can fail: the interrupted render's own image is another one.
    EXPECT_FALSE(read_file(dir.file("cut.exr")) == a);
}

}  // namespace

TEST(CheckpointCli, VolpathResumedAfterSigtermIsBitIdentical) {
    expect_resume_is_bit_identical("volpath", "2000", 8);
}

// Past the coarse stage's decision (4 spp) and the full stage's confirmation at 16 spp later.
TEST(CheckpointCli, GuidedVolpathResumedAfterSigtermIsBitIdentical) {
    expect_resume_is_bit_identical("guided_volpath", "120", 24);
}

TEST(CheckpointCli, OtherOptionsOrCorruptCheckpointsAreRefused) {
    TempDir dir("checkpoint-refused");
    const std::string ckpt = dir.file("render.ckpt");
    const std::vector<std::string> base = fogbox_render("volpath", "4");
    ASSERT_EQ(run_cli(with(base, {"--checkpoint", ckpt, "-o", dir.file("a.exr")})).exit_code, 0);
    const std::string saved = read_file(ckpt);

    CliResult r = run_cli(with(fogbox_render("volpath", "8"), {"--resume", ckpt, "-o", dir.file("b.exr")}));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("render.ckpt"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("spp target 4 (this render: 8)"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("b.exr")));

    r = run_cli(with(fogbox_render("guided_volpath", "4"), {"--resume", ckpt, "-o", dir.file("b.exr")}));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("integrator configuration"), std::string::npos) << r.err;

    // Another build's checkpoint (its identity edited, the checksum made again).
    volguide::Checkpoint other = volguide::load_checkpoint(ckpt);
    other.identity.build = "another-build";
    volguide::save_checkpoint(dir.file("other.ckpt"), other);
    r = run_cli(with(base, {"--resume", dir.file("other.ckpt"), "-o", dir.file("b.exr")}));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("written by another build (another-build; this one is "), std::string::npos) << r.err;

    std::ofstream(ckpt, std::ios::binary | std::ios::trunc) << saved.substr(0, saved.size() / 2);
    const std::string truncated = read_file(ckpt);
    r = run_cli(with(base, {"--resume", ckpt, "--checkpoint", ckpt, "-o", dir.file("b.exr")}));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("checksum"), std::string::npos) << r.err;
    EXPECT_EQ(read_file(ckpt), truncated) << "the refused checkpoint was overwritten";
    EXPECT_FALSE(std::filesystem::exists(dir.file("b.exr")));
}

// Integrators whose state a checkpoint cannot hold are refused before rendering, naming why: a light
// tracer (on a surface scene: ptracer renders no media) and openpgl_volpath.
TEST(CheckpointCli, IntegratorsWithoutRenderStateAreRefused) {
    TempDir dir("checkpoint-unsupported");
    const std::string surfaces = dir.write(
        "surfaces.xml",
        R"(<scene version="3.0.0"><integrator type="ptracer"/><shape type="rectangle"><bsdf type="diffuse"/></shape>
<emitter type="point"><point name="position" value="0, 0, 2"/><rgb name="intensity" value="5"/></emitter>
<sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
<film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor></scene>)");
    const std::string openpgl =
        dir.write("openpgl.xml", R"(<scene version="3.0.0"><integrator type="openpgl_volpath"/></scene>)");
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"render", surfaces, "--spp", "2"}, "light tracer"},
        {with(fogbox_render("volpath", "4"), {"-D", "integrator_xml=" + openpgl}), "Open PGL field"}};
    for (const auto& [args, reason] : cases) {
        const CliResult r = run_cli(with(args, {"--checkpoint", dir.file("r.ckpt"), "-o", dir.file("r.exr")}));
        EXPECT_NE(r.exit_code, 0) << reason;
        EXPECT_NE(r.err.find("cannot checkpoint this render"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(reason), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir.file("r.exr"))) << reason;
    }
}
