// The `volguide` command line as users and scripts see it: exit codes, one-line errors, `diff`
// metrics, and small renders (outputs, variance image, stats, seeds, thread-count independence).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "support/test_support.h"
#include "volguide/core/image.h"
#include "volguide/render/image_io.h"

namespace fs = std::filesystem;

namespace volguide {
namespace {

struct CliRun {
    int code = -1;
    std::string out, err;
};

std::string slurp(const fs::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

class Cli : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ =
            fs::temp_directory_path() /
            ("volguide_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
             "_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        if (!HasFailure()) fs::remove_all(dir_);
    }
    // Runs the CLI in the test directory (arguments are passed through the shell as given).
    CliRun run(const std::string& args) {
        std::string cmd =
            "cd '" + dir_.string() + "' && '" + test::cli_path() + "' " + args + " >stdout.txt 2>stderr.txt";
        int status = std::system(cmd.c_str());
        CliRun r;
        r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = slurp(dir_ / "stdout.txt");
        r.err = slurp(dir_ / "stderr.txt");
        return r;
    }
    void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
    fs::path path(const std::string& name) const { return dir_ / name; }

    fs::path dir_;
};

int count_lines(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

TEST_F(Cli, UsageErrorsExitWithTwo) {
    for (const char* args :
         {"", "frobnicate", "render", "render s.xml --spp 0", "render s.xml --spp abc", "render s.xml -D foo",
          "render s.xml --bogus", "render s.xml -o out.jpg", "render s.xml --threads 0",
          "render s.xml --time -1", "diff a.exr", "info", "diff a.exr b.exr --error-image e.txt", "convert a.exr", "convert a.exr b.jpg",
          "render s.xml --reference r.png"}) {
        CliRun r = run(args);
        EXPECT_EQ(r.code, 2) << "args: " << args << "\nstderr: " << r.err;
        EXPECT_FALSE(r.err.empty()) << args;
        EXPECT_TRUE(r.out.empty()) << args;
    }
    EXPECT_EQ(run("--help").code, 0);
    EXPECT_EQ(run("render --help").code, 0);
}

TEST_F(Cli, DiffMetrics) {
    Image image(4, 3, Color3(1.1f, 1.1f, 1.1f)), reference(4, 3, Color3(1.f));
    image.at(0, 0) = Color3(0.f);  // one black pixel: error 1 on three channels
    write_exr(path("i.exr").string(), image);
    write_exr(path("r.exr").string(), reference);
    // Float EXR values: recompute the expectation from what was stored.
    const double d = double(1.1f) - 1.0, n = 36;
    const double rel2 = (33 * d * d / 1.01 + 3 * 1 / 1.01) / n, rel3 = (33 * d * d / 1.001 + 3 / 1.001) / n;
    const double mse = (33 * d * d + 3) / n, mean = 33 * double(1.1f) / n;

    CliRun text = run("diff i.exr r.exr");
    ASSERT_EQ(text.code, 0) << text.err;
    EXPECT_NE(text.out.find("relMSE(1e-2): "), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("relMSE(1e-3): "), std::string::npos);
    EXPECT_NE(text.out.find("MSE: "), std::string::npos);
    EXPECT_NE(text.out.find("ratio: "), std::string::npos);

    CliRun js = run("diff i.exr r.exr --json --error-image err.exr");
    ASSERT_EQ(js.code, 0) << js.err;
    auto j = nlohmann::json::parse(js.out);
    EXPECT_NEAR(j["relmse_1e-2"].get<double>(), rel2, 1e-9);
    EXPECT_NEAR(j["relmse_1e-3"].get<double>(), rel3, 1e-9);
    EXPECT_NEAR(j["mse"].get<double>(), mse, 1e-9);
    EXPECT_NEAR(j["mean"].get<double>(), mean, 1e-9);
    EXPECT_NEAR(j["reference_mean"].get<double>(), 1.0, 1e-12);
    EXPECT_NEAR(j["ratio"].get<double>(), mean, 1e-9);
    Image err = read_image(path("err.exr").string());
    ASSERT_EQ(err.width, 4);
    EXPECT_NEAR(err.at(0, 0).g, 1 / 1.01, 1e-6);
    EXPECT_NEAR(err.at(2, 1).r, d * d / 1.01, 1e-6);

    // Nothing to trim below 10 000 pixels.
    EXPECT_NEAR(j["relmse_1e-3_trimmed"].get<double>(), rel3, 1e-9);
    EXPECT_NEAR(j["relmse_1e-2_trimmed"].get<double>(), rel2, 1e-9);
    // A PNG error image is a false-colour map: the black pixel's error (1) is brighter than the rest.
    ASSERT_EQ(run("diff i.exr r.exr --error-image heat.png").code, 0);
    Image heat = read_image(path("heat.png").string());
    EXPECT_GT(heat.at(0, 0).r, heat.at(1, 0).r);

    write_exr(path("small.exr").string(), Image(2, 2));
    CliRun mismatch = run("diff i.exr small.exr");
    EXPECT_EQ(mismatch.code, 1);
    EXPECT_EQ(mismatch.err.rfind("volguide: i.exr: ", 0), 0u) << mismatch.err;
    EXPECT_EQ(count_lines(mismatch.err), 1) << mismatch.err;

    CliRun missing = run("diff nothere.exr r.exr");
    EXPECT_EQ(missing.code, 1);
    EXPECT_EQ(missing.err.rfind("volguide: ", 0), 0u);
    EXPECT_EQ(count_lines(missing.err), 1) << missing.err;
}

// A sphere (Mitsuba's default diffuse material) under a constant environment: noisy, cheap.
const char* kCliScene = R"(<scene version="3.0.0">
    <default name="spp" value="4"/>
    <integrator type="moment">
        <integrator type="path"/>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world">
            <lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/>
        </transform>
        <film type="hdrfilm">
            <integer name="width" value="16"/>
            <integer name="height" value="12"/>
            <rfilter type="gaussian"/>
        </film>
        <sampler type="independent">
            <integer name="sample_count" value="$spp"/>
        </sampler>
    </sensor>
    <emitter type="constant">
        <rgb name="radiance" value="0.25, 0.5, 1"/>
    </emitter>
    <shape type="sphere"/>
</scene>
)";

TEST_F(Cli, RenderWritesImageVarianceAndStats) {
    write("s.xml", kCliScene);
    CliRun r = run("render s.xml --spp 8 --seed 3 --threads 1 --stats st.json --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << r.err;  // --quiet
    EXPECT_NE(r.out.find("spp: 8"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("s.exr"), std::string::npos) << r.out;
    ASSERT_TRUE(fs::exists(path("s.exr")));  // default output: <scene stem>.exr
    ASSERT_TRUE(fs::exists(path("s_var.exr")));
    Image img = read_image(path("s.exr").string());
    EXPECT_EQ(img.width, 16);
    EXPECT_EQ(img.height, 12);
    // The corner sees the environment only.
    EXPECT_NEAR(img.at(0, 0).r, 0.25f, 1e-5f);
    EXPECT_NEAR(img.at(0, 0).b, 1.f, 1e-5f);
    auto st = nlohmann::json::parse(slurp(path("st.json")));
    EXPECT_EQ(st["spp"].get<int>(), 8);
    EXPECT_EQ(st["seed"].get<uint64_t>(), 3u);
    EXPECT_EQ(st["threads"].get<int>(), 1);
    EXPECT_EQ(st["samples"].get<uint64_t>(), 16u * 12u * 8u);

    // Same seed, two threads: the same bits.
    CliRun r2 = run("render s.xml -o two.exr --spp 8 --seed 3 --threads 2 --quiet");
    ASSERT_EQ(r2.code, 0) << r2.err;
    Image two = read_image(path("two.exr").string());
    ASSERT_EQ(two.pixels.size(), img.pixels.size());
    EXPECT_EQ(std::memcmp(two.pixels.data(), img.pixels.data(), img.pixels.size() * sizeof(Color3)), 0);
    // Another seed: other noise.
    ASSERT_EQ(run("render s.xml -o other.exr --spp 8 --seed 4 --quiet").code, 0);
    Image other = read_image(path("other.exr").string());
    EXPECT_NE(std::memcmp(other.pixels.data(), img.pixels.data(), img.pixels.size() * sizeof(Color3)), 0);

    // -D sets a <default>; PNG preview output; several outputs from one render.
    CliRun d = run("render s.xml -D spp=2 -o prev.png -o both.exr --stats d.json --quiet");
    ASSERT_EQ(d.code, 0) << d.err;
    EXPECT_EQ(nlohmann::json::parse(slurp(path("d.json")))["spp"].get<int>(), 2);
    std::string png = slurp(path("prev.png"));
    ASSERT_GE(png.size(), 8u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    EXPECT_TRUE(fs::exists(path("prev_var.exr")));  // named after the first output
    EXPECT_EQ(read_image(path("both.exr").string()).width, 16);
}

// --variance writes the per-sample variance for an integrator that is not `moment`: the same image
// moment's would be (same seed, same samples).
TEST_F(Cli, VarianceFlagWritesTheVarianceOfAnyIntegrator) {
    std::string plain = kCliScene;
    const std::string moment = R"(<integrator type="moment">
        <integrator type="path"/>
    </integrator>)";
    const size_t at = plain.find(moment);
    ASSERT_NE(at, std::string::npos);
    plain.replace(at, moment.size(), R"(<integrator type="path"/>)");
    write("m.xml", kCliScene);
    write("p.xml", plain);
    ASSERT_EQ(run("render m.xml --spp 8 --seed 3 --quiet").code, 0);
    ASSERT_EQ(run("render p.xml --spp 8 --seed 3 --quiet").code, 0);
    EXPECT_FALSE(fs::exists(path("p_var.exr")));
    CliRun r = run("render p.xml --spp 8 --seed 3 --variance --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_TRUE(fs::exists(path("p_var.exr")));
    const Image a = read_image(path("m_var.exr").string()), b = read_image(path("p_var.exr").string());
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    EXPECT_EQ(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Color3)), 0);
    double total = 0;
    for (const Color3& c : b.pixels) total += c.r + c.g + c.b;
    EXPECT_GT(total, 0.0);  // the sphere's pixels are noisy
}

// Ctrl-C: the render stops, the completed passes are written, the exit code is 0.
TEST_F(Cli, ConvertScalesByExposure) {
    Image image(3, 2, Color3(0.25f, 0.5f, 1.f));
    write_exr(path("a.exr").string(), image);
    ASSERT_EQ(run("convert a.exr b.exr --exposure 1").code, 0);
    Image b = read_image(path("b.exr").string());
    EXPECT_FLOAT_EQ(b.at(2, 1).r, 0.5f);
    EXPECT_FLOAT_EQ(b.at(2, 1).b, 2.f);
    CliRun png = run("convert a.exr a.png");
    ASSERT_EQ(png.code, 0) << png.err;
    EXPECT_NEAR(read_image(path("a.png").string()).at(0, 0).g, 0.5f, 0.01f);  // sRGB round trip
    CliRun missing = run("convert nothere.exr x.png");
    EXPECT_EQ(missing.code, 1);
    EXPECT_EQ(count_lines(missing.err), 1) << missing.err;
}

TEST_F(Cli, ReferenceGivesRelMseAndAConvergenceCurve) {
    write("s.xml", kCliScene);
    ASSERT_EQ(run("render s.xml -o ref.exr --spp 64 --seed 9 --quiet").code, 0);
    CliRun r = run("render s.xml -o img.exr --spp 10 --seed 3 --reference ref.exr --stats st.json --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("relMSE vs reference: "), std::string::npos) << r.out;
    auto st = nlohmann::json::parse(slurp(path("st.json")));
    // The final figure is exactly what `diff` computes from the written images.
    CliRun d = run("diff img.exr ref.exr --json");
    ASSERT_EQ(d.code, 0) << d.err;
    auto dj = nlohmann::json::parse(d.out);
    EXPECT_DOUBLE_EQ(st["reference"]["relmse_1e-2"].get<double>(), dj["relmse_1e-2"].get<double>());
    EXPECT_DOUBLE_EQ(st["reference"]["mse"].get<double>(), dj["mse"].get<double>());
    EXPECT_EQ(st["reference"]["file"].get<std::string>(), "ref.exr");
    // Points at 1, 2, 4, 8 spp and the final 10, with non-decreasing times; more samples, less error.
    const auto& curve = st["convergence"];
    ASSERT_EQ(curve.size(), 5u) << curve.dump();
    const int expected[] = {1, 2, 4, 8, 10};
    for (size_t k = 0; k < curve.size(); ++k) {
        EXPECT_EQ(curve[k]["spp"].get<int>(), expected[k]);
        if (k > 0) {
            EXPECT_GE(curve[k]["seconds"].get<double>(), curve[k - 1]["seconds"].get<double>());
        }
    }
    EXPECT_LT(curve[4]["relmse_1e-2"].get<double>(), curve[0]["relmse_1e-2"].get<double>());
    EXPECT_DOUBLE_EQ(curve[4]["relmse_1e-2"].get<double>(), dj["relmse_1e-2"].get<double>());

    // A reference of another size is an input error before rendering.
    write_exr(path("small.exr").string(), Image(2, 2));
    CliRun bad = run("render s.xml -o x.exr --reference small.exr --quiet");
    EXPECT_EQ(bad.code, 1);
    EXPECT_EQ(bad.err.rfind("volguide: small.exr: ", 0), 0u) << bad.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

TEST_F(Cli, InterruptWritesTheCompletedPasses) {
    write("s.xml", kCliScene);
    for (int attempt = 0; attempt < 4; ++attempt) {
        fs::remove(path("int.exr"));
        pid_t pid = fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            if (chdir(dir_.c_str()) != 0) _exit(99);
            FILE* out = freopen("int_stdout.txt", "w", stdout);
            FILE* err = freopen("int_stderr.txt", "w", stderr);
            (void)out;
            (void)err;
            std::string cli = test::cli_path();
            execl(cli.c_str(), cli.c_str(), "render", "s.xml", "-o", "int.exr", "--spp", "1000000", "--stats",
                  "int.json", "--threads", "1", static_cast<char*>(nullptr));
            _exit(98);
        }
        // Wait for the first pass (a few milliseconds of work) before interrupting; longer on retries.
        std::this_thread::sleep_for(std::chrono::milliseconds(500 << attempt));
        kill(pid, SIGINT);
        int status = 0;
        waitpid(pid, &status, 0);
        ASSERT_TRUE(WIFEXITED(status));
        std::string err = slurp(path("int_stderr.txt"));
        if (WEXITSTATUS(status) == 1 && err.find("before the first pass") != std::string::npos) continue;
        ASSERT_EQ(WEXITSTATUS(status), 0) << err;
        auto st = nlohmann::json::parse(slurp(path("int.json")));
        EXPECT_TRUE(st["cancelled"].get<bool>());
        int spp = st["spp"].get<int>();
        EXPECT_GE(spp, 1);
        EXPECT_LT(spp, 1000000);
        Image img = read_image(path("int.exr").string());
        EXPECT_EQ(img.width, 16);
        EXPECT_TRUE(fs::exists(path("int_var.exr")));
        EXPECT_NE(slurp(path("int_stdout.txt")).find("interrupted"), std::string::npos);
        // Atomic writes: no temporary files left behind.
        for (const auto& entry : fs::directory_iterator(dir_))
            EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
        return;
    }
    FAIL() << "the render never completed its first pass before the interrupt";
}

TEST_F(Cli, InputErrorsAreOneLineWithExitOne) {
    write("s.xml", kCliScene);
    CliRun unknown = run("render s.xml -D nosuch=1");
    EXPECT_EQ(unknown.code, 1);
    EXPECT_EQ(unknown.err.rfind("volguide: ", 0), 0u) << unknown.err;
    EXPECT_EQ(count_lines(unknown.err), 1) << unknown.err;
    EXPECT_FALSE(fs::exists(path("s.exr")));  // nothing written on error

    write("broken.xml", "<scene version=\"3.0.0\">\n  <shape type=\"nosuchshape\"/>\n</scene>\n");
    CliRun broken = run("render broken.xml");
    EXPECT_EQ(broken.code, 1);
    EXPECT_NE(broken.err.find("broken.xml:2"), std::string::npos) << broken.err;
    EXPECT_EQ(count_lines(broken.err), 1) << broken.err;
    EXPECT_FALSE(fs::exists(path("broken.exr")));

    CliRun missing = run("render missing.xml");
    EXPECT_EQ(missing.code, 1);
    EXPECT_EQ(missing.err.rfind("volguide: missing.xml", 0), 0u) << missing.err;
    EXPECT_EQ(count_lines(missing.err), 1);
}

TEST_F(Cli, InfoPrintsTheFilmMemory) {
    write("s.xml", kCliScene);
    CliRun r = run("info s.xml");
    ASSERT_EQ(r.code, 0) << r.err;
    // 16 x 12 pixels at 128 bytes each.
    EXPECT_NE(r.out.find("film memory: 24.0 KiB (the limit is "), std::string::npos) << r.out;
}

TEST_F(Cli, InfoSummarisesTheScene) {
    write("s.xml", kCliScene);
    CliRun r = run("info s.xml");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("resolution: 16 x 12"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("spp: 4"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("shapes: 1"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("emitters: 1"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("integrator: moment"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace volguide
