// One image on many machines (issue 23, docs/distributed.md) through the CLI: `train` once and
// `render --field`, chunks `render --samples FIRST:COUNT` merged by `merge`, mismatched fields and
// parts rejected, SIGTERM leaving a partial chunk that merges.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "support/test_support.h"
#include "volguide/render/image_compare.h"
#include "volguide/render/image_io.h"
#include "volguide/render/render_part.h"

namespace fs = std::filesystem;

namespace volguide {
namespace {

struct ChunkRun {
    int code = -1;
    std::string out, err;
};

std::string slurp_file(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

// Fog in a box over a diffuse floor, lit by a point light; guided_volpath with guided RR and
// splitting (so the training file carries a pixel estimate too) and a gaussian filter (pixels
// are sum(w L) / sum(w) over neighbouring samples). $albedo and $photons make other scenes and
// other integrator configurations; $allocation (default false) the allocation learned while rendering,
// which a training file learns in its pre-pass instead.
const char* kDistributedScene = R"(<scene version="3.0.0">
    <default name="photons" value="20000"/>
    <default name="albedo" value="0.9"/>
    <default name="allocation" value="false"/>
    <integrator type="moment">
        <integrator type="guided_volpath">
            <integer name="photons" value="$photons"/>
            <integer name="leaf_samples" value="400"/>
            <string name="rrs" value="grrs"/>
            <integer name="max_depth" value="8"/>
            <boolean name="allocation" value="$allocation"/>
        </integrator>
    </integrator>
    <medium type="homogeneous" id="fog">
        <rgb name="sigma_t" value="0.6, 0.3, 0.9"/>
        <rgb name="albedo" value="$albedo"/>
        <phase type="hg"><float name="g" value="0.6"/></phase>
    </medium>
    <shape type="cube"><bsdf type="null"/><ref name="interior" id="fog"/></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/><translate y="-1.01"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    </shape>
    <emitter type="point"><point name="position" value="1.6, 0.3, 0"/><rgb name="intensity" value="8"/></emitter>
    <sensor type="perspective">
        <float name="fov" value="50"/>
        <transform name="to_world"><lookat origin="-0.5, 0.8, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="12"/>
            <rfilter type="gaussian"/></film>
    </sensor>
</scene>
)";

// The same without a pre-pass (volpath), for the parts of an unguided render.
std::string volpath_scene() {
    std::string s = kDistributedScene;
    const size_t a = s.find("<integrator type=\"guided_volpath\">");
    const size_t b = s.find("</integrator>", a) + std::string("</integrator>").size();
    return s.replace(a, b - a, "<integrator type=\"volpath\"><integer name=\"max_depth\" value=\"8\"/></integrator>");
}

class Distributed : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("volguide_dist_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                "_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        write("s.xml", kDistributedScene);
    }
    void TearDown() override {
        if (!HasFailure()) fs::remove_all(dir_);
    }
    ChunkRun run(const std::string& args) {
        const std::string cmd =
            "cd '" + dir_.string() + "' && '" + test::cli_path() + "' " + args + " >stdout.txt 2>stderr.txt";
        const int status = std::system(cmd.c_str());
        ChunkRun r;
        r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = slurp_file(dir_ / "stdout.txt");
        r.err = slurp_file(dir_ / "stderr.txt");
        return r;
    }
    void ok(const std::string& args) {
        const ChunkRun r = run(args);
        ASSERT_EQ(r.code, 0) << args << "\n" << r.err;
    }
    void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    Image image(const std::string& name) const { return read_image(path(name)); }
    RenderPart part(const std::string& name) const { return read_part(path(name)); }

    fs::path dir_;
};

bool identical(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height) return false;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            if (a.pixels[i][c] != b.pixels[i][c]) return false;
    return true;
}

// Plain relMSE without the epsilon: mean of (a - b)^2 / b^2 over channels with b != 0.
double strict_relmse(const Image& a, const Image& b) {
    double sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double r = b.pixels[i][c], d = double(a.pixels[i][c]) - r;
            if (r == 0) {
                sum += d == 0 ? 0 : 1;
            } else {
                sum += d * d / (r * r);
            }
            ++n;
        }
    return sum / double(n);
}

// With the allocation (issue 59) the training file learns it in its pre-pass and carries it: every
// render from it, in one process or in chunks, with any thread count, samples the same distributions.
TEST_F(Distributed, TrainedAllocationChunksMergeEqualTheSingleProcessRender) {
    ok("train s.xml -D allocation=true -o f.vgt --seed 5 --threads 1 --quiet");
    ok("render s.xml -D allocation=true --field f.vgt --seed 5 --spp 8 --threads 2 -o single.exr --stats s.json "
       "--quiet");
    ok("render s.xml -D allocation=true --field f.vgt --seed 5 --spp 8 --threads 1 -o one.exr --quiet");
    EXPECT_TRUE(identical(image("single.exr"), image("one.exr")));
    ok("render s.xml -D allocation=true --field f.vgt --seed 5 --samples 0:3 --threads 1 -o c0.exr --quiet");
    ok("render s.xml -D allocation=true --field f.vgt --seed 5 --samples 3:5 --threads 2 -o c1.exr --quiet");
    const ChunkRun merged = run("merge c1.exr c0.exr -o merged.exr");
    ASSERT_EQ(merged.code, 0) << merged.err;
    // As ChunksMergeIntoTheSingleProcessRender: float32 rounding of sums made in other passes.
    EXPECT_LT(strict_relmse(image("merged.exr"), image("single.exr")), 1e-12);
    // The training file carries an allocation (its summary is in the render's statistics) ...
    const std::string stats = slurp_file(dir_ / "s.json");
    EXPECT_NE(stats.find("\"allocation_gain\""), std::string::npos) << stats;
    // ... that changes the image (the comparisons above could fail).
    ok("train s.xml -o g.vgt --seed 5 --threads 1 --quiet");
    ok("render s.xml --field g.vgt --seed 5 --spp 8 --threads 2 -o configured.exr --quiet");
    EXPECT_FALSE(identical(image("single.exr"), image("configured.exr")));
}

TEST_F(Distributed, TrainThenRenderWithFieldGivesTheRendersImage) {
    ok("render s.xml --seed 5 --spp 4 --threads 2 -o full.exr --quiet");
    ok("train s.xml -o f.vgt --seed 5 --threads 1 --quiet");
    const ChunkRun r = run("render s.xml --field f.vgt --seed 5 --spp 4 --threads 2 -o with_field.exr --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    // The same field and pixel estimate, the same samples: the same image, bit for bit.
    EXPECT_TRUE(identical(image("full.exr"), image("with_field.exr")));
    EXPECT_TRUE(identical(image("full_var.exr"), image("with_field_var.exr")));
    EXPECT_EQ(part("full.exr").info.field, part("with_field.exr").info.field);
    EXPECT_NE(part("full.exr").info.field, "none");
    // `info --field` reads training files too: what it was trained for, and the field.
    const ChunkRun info = run("info --field f.vgt");
    ASSERT_EQ(info.code, 0) << info.err;
    EXPECT_NE(info.out.find("field fingerprint: " + part("full.exr").info.field), std::string::npos) << info.out;
    EXPECT_NE(info.out.find("leaves: "), std::string::npos) << info.out;
    // A field trained with another seed is another field.
    ok("train s.xml -o g.vgt --seed 6 --quiet");
    ok("render s.xml --field g.vgt --seed 5 --spp 4 -o other.exr --quiet");
    EXPECT_NE(part("full.exr").info.field, part("other.exr").info.field);
}

TEST_F(Distributed, FieldsOfOtherScenesConfigurationsOrCorruptFilesAreRejected) {
    ok("train s.xml -o f.vgt --seed 5 --quiet");
    const ChunkRun scene = run("render s.xml -D albedo=0.5 --field f.vgt --spp 1 -o x.exr --quiet");
    EXPECT_EQ(scene.code, 1);
    EXPECT_EQ(scene.err.rfind("volguide: f.vgt: trained for another scene", 0), 0u) << scene.err;
    const ChunkRun config = run("render s.xml -D photons=30000 --field f.vgt --spp 1 -o x.exr --quiet");
    EXPECT_EQ(config.code, 1);
    EXPECT_EQ(config.err.rfind("volguide: f.vgt: trained with another integrator configuration", 0), 0u)
        << config.err;
    EXPECT_NE(config.err.find("photons=30000"), std::string::npos) << config.err;

    std::string bytes = slurp_file(path("f.vgt"));
    bytes[bytes.size() / 2] ^= 0x5a;
    write("corrupt.vgt", bytes);
    const ChunkRun corrupt = run("render s.xml --field corrupt.vgt --spp 1 -o x.exr --quiet");
    EXPECT_EQ(corrupt.code, 1);
    EXPECT_EQ(corrupt.err.rfind("volguide: corrupt.vgt: training file checksum mismatch", 0), 0u) << corrupt.err;
    write("short.vgt", slurp_file(path("f.vgt")).substr(0, 100));
    EXPECT_EQ(run("render s.xml --field short.vgt --spp 1 -o x.exr --quiet").code, 1);
    write("notafield.vgt", "hello");
    const ChunkRun magic = run("render s.xml --field notafield.vgt --spp 1 -o x.exr --quiet");
    EXPECT_EQ(magic.code, 1);
    EXPECT_NE(magic.err.find("not a volguide training file"), std::string::npos) << magic.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));

    write("v.xml", volpath_scene());
    const ChunkRun none = run("train v.xml -o v.vgt --quiet");
    EXPECT_EQ(none.code, 1);
    EXPECT_NE(none.err.find("has no pre-pass"), std::string::npos) << none.err;
    EXPECT_FALSE(fs::exists(path("v.vgt")));
}

TEST_F(Distributed, ChunksMergeIntoTheSingleProcessRender) {
    ok("train s.xml -o f.vgt --seed 7 --quiet");
    ok("render s.xml --field f.vgt --seed 7 --spp 9 --threads 2 -o full.exr --quiet");
    ok("render s.xml --field f.vgt --seed 7 --samples 0:3 --threads 1 -o c0.exr --quiet");
    ok("render s.xml --field f.vgt --seed 7 --samples 3:2 --threads 2 -o c1.exr --quiet");
    ok("render s.xml --field f.vgt --seed 7 --samples 5:4 --threads 2 -o c2.exr --quiet");
    EXPECT_EQ(format_ranges(part("c1.exr").info.samples), "3:2");
    const ChunkRun merged = run("merge c2.exr c0.exr c1.exr -o merged.exr");
    ASSERT_EQ(merged.code, 0) << merged.err;
    EXPECT_NE(merged.out.find("samples: 0:9"), std::string::npos) << merged.out;
    EXPECT_EQ(merged.out.find("gaps"), std::string::npos) << merged.out;
    const RenderPart m = part("merged.exr"), full = part("full.exr");
    EXPECT_EQ(format_ranges(m.info.samples), "0:9");
    EXPECT_EQ(m.info.field, full.info.field);
    // Not bit-identical: the chunks sum their samples in other passes (render_part.h); float32 rounding.
    const double rel = strict_relmse(m.mean, full.mean);
    EXPECT_LT(rel, 1e-12) << rel;
    EXPECT_LT(compare_images(m.mean, full.mean).relmse_1e2, 1e-12);
    for (size_t i = 0; i < m.weight.size(); ++i) EXPECT_NEAR(m.weight[i], full.weight[i], 1e-5 * full.weight[i]);
    // Variances through their second moments (cancellation: a looser bound).
    ASSERT_FALSE(m.variance.pixels.empty());
    EXPECT_LT(compare_images(image("merged_var.exr"), image("full_var.exr")).relmse_1e2, 1e-9);

    // A merged image is a part too: merging it with a further chunk extends it.
    ok("render s.xml --field f.vgt --seed 7 --samples 9:2 -o c3.exr --quiet");
    ok("merge merged.exr c3.exr -o more.exr");
    EXPECT_EQ(format_ranges(part("more.exr").info.samples), "0:11");
}

TEST_F(Distributed, UnguidedChunksMergeToo) {
    write("v.xml", volpath_scene());
    ok("render v.xml --seed 3 --spp 6 -o full.exr --quiet");
    ok("render v.xml --seed 3 --samples 0:4 -o a.exr --quiet");
    ok("render v.xml --seed 3 --samples 4:2 -o b.exr --quiet");
    ok("merge a.exr b.exr -o m.exr");
    EXPECT_EQ(part("m.exr").info.field, "none");
    EXPECT_LT(strict_relmse(part("m.exr").mean, part("full.exr").mean), 1e-12);
}

TEST_F(Distributed, MismatchedPartsAreRejectedAndGapsReported) {
    ok("train s.xml -o f.vgt --seed 7 --quiet");
    ok("train s.xml -o g.vgt --seed 8 --quiet");
    ok("render s.xml --field f.vgt --seed 7 --samples 0:2 -o a.exr --quiet");
    ok("render s.xml --field f.vgt --seed 7 --samples 1:2 -o overlap.exr --quiet");
    ok("render s.xml --field f.vgt --seed 8 --samples 2:2 -o seed.exr --quiet");
    ok("render s.xml --field g.vgt --seed 7 --samples 2:2 -o field.exr --quiet");
    ok("render s.xml --seed 7 -D albedo=0.5 --samples 2:2 -o scene.exr --quiet");
    ok("render s.xml --field f.vgt --seed 7 --samples 4:2 -o gap.exr --quiet");
    write_exr(path("plain.exr"), Image(16, 12));
    struct Case {
        const char* part;
        const char* message;
    };
    for (const Case& c : {Case{"overlap.exr", "samples 1:1 are also in a.exr"}, Case{"seed.exr", "another seed"},
                          Case{"field.exr", "another guiding field"}, Case{"scene.exr", "another scene"},
                          Case{"plain.exr", "not a part of a volguide render"}}) {
        const ChunkRun r = run(std::string("merge a.exr ") + c.part + " -o m.exr");
        EXPECT_EQ(r.code, 1) << c.part;
        EXPECT_EQ(r.err.rfind(std::string("volguide: ") + c.part + ": ", 0), 0u) << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("m.exr"))) << c.part;
    }
    const ChunkRun gap = run("merge a.exr gap.exr -o m.exr");
    ASSERT_EQ(gap.code, 0) << gap.err;
    EXPECT_NE(gap.out.find("gaps: 2:2"), std::string::npos) << gap.out;
    EXPECT_NE(gap.err.find("missing"), std::string::npos) << gap.err;
    EXPECT_EQ(format_ranges(part("m.exr").info.samples), "0:2,4:2");
}

TEST_F(Distributed, SigtermLeavesAPartialChunkThatMerges) {
    ok("train s.xml -o f.vgt --seed 7 --quiet");
    ok("render s.xml --field f.vgt --seed 7 --samples 0:4 -o head.exr --quiet");
    for (int attempt = 0; attempt < 4; ++attempt) {
        fs::remove(path("tail.exr"));
        const pid_t pid = fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            if (chdir(dir_.c_str()) != 0) _exit(99);
            if (!freopen("tail_stdout.txt", "w", stdout) || !freopen("tail_stderr.txt", "w", stderr)) _exit(97);
            const std::string cli = test::cli_path();
            execl(cli.c_str(), cli.c_str(), "render", "s.xml", "--field", "f.vgt", "--seed", "7", "--samples",
                  "4:1000000", "-o", "tail.exr", "--threads", "1", "--quiet", static_cast<char*>(nullptr));
            _exit(98);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(400 << attempt));
        kill(pid, SIGTERM);
        int status = 0;
        waitpid(pid, &status, 0);
        ASSERT_TRUE(WIFEXITED(status));
        const std::string err = slurp_file(path("tail_stderr.txt"));
        if (WEXITSTATUS(status) == 1 && err.find("before the first pass") != std::string::npos) continue;
        ASSERT_EQ(WEXITSTATUS(status), 0) << err;
        EXPECT_NE(slurp_file(path("tail_stdout.txt")).find("interrupted"), std::string::npos);
        for (const auto& entry : fs::directory_iterator(dir_))
            EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
        const RenderPart tail = part("tail.exr");
        ASSERT_EQ(tail.info.samples.size(), 1u);
        const uint64_t count = tail.info.samples[0].count;
        EXPECT_EQ(tail.info.samples[0].first, 4u);
        EXPECT_GE(count, 1u);
        EXPECT_LT(count, 1000000u);
        ok("merge head.exr tail.exr -o m.exr");
        const std::string total = std::to_string(4 + count);
        ok("render s.xml --field f.vgt --seed 7 --spp " + total + " -o full.exr --quiet");
        EXPECT_EQ(format_ranges(part("m.exr").info.samples), "0:" + total);
        EXPECT_LT(strict_relmse(part("m.exr").mean, part("full.exr").mean), 1e-12);
        return;
    }
    FAIL() << "the chunk never completed a pass before SIGTERM";
}

TEST_F(Distributed, SigtermDuringTrainingWritesNothing) {
    for (int attempt = 0; attempt < 3; ++attempt) {
        const pid_t pid = fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            if (chdir(dir_.c_str()) != 0) _exit(99);
            if (!freopen("train_stdout.txt", "w", stdout) || !freopen("train_stderr.txt", "w", stderr)) _exit(97);
            const std::string cli = test::cli_path();
            execl(cli.c_str(), cli.c_str(), "train", "s.xml", "-D", "photons=200000000", "-o", "big.vgt",
                  "--threads", "1", "--quiet", static_cast<char*>(nullptr));
            _exit(98);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(500 << attempt));
        kill(pid, SIGTERM);
        int status = 0;
        waitpid(pid, &status, 0);
        // Killed before the handler was installed (a very slow start): try again, later.
        if (WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) continue;
        ASSERT_TRUE(WIFEXITED(status));
        EXPECT_EQ(WEXITSTATUS(status), 1);
        EXPECT_NE(slurp_file(path("train_stderr.txt")).find("big.vgt: interrupted during training; nothing was written"),
                  std::string::npos)
            << slurp_file(path("train_stderr.txt"));
        EXPECT_FALSE(fs::exists(path("big.vgt")));
        return;
    }
    FAIL() << "train never got as far as installing its signal handler";
}

TEST_F(Distributed, UsageErrors) {
    for (const char* args : {"render s.xml --samples 3", "render s.xml --samples 0:0", "render s.xml --samples a:b",
                             "render s.xml --samples 0:4 --spp 4", "train s.xml", "merge a.exr",
                             "merge a.exr -o m.png"}) {
        const ChunkRun r = run(args);
        EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    }
}

}  // namespace
}  // namespace volguide

