// The equal-time benchmark's scenes (bench/scenes, issue 5) load and render with the baseline
// methods (volpath, volpath + equiangular, volpath with the bounded roulette), and their images are finite and not black (a mistake in a scene shows up here, not an
// hour into a benchmark run).
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "support/cli.h"
#include "support/test_support.h"
#include "volguide/render/image_io.h"

using namespace volguide;
using namespace volguide::test;

class BenchScene : public ::testing::TestWithParam<const char*> {};

TEST_P(BenchScene, RendersWithTheBaselines) {
    TempDir dir(std::string("bench-scene-") + GetParam());
    const std::string scene = source_dir() + "/bench/scenes/" + GetParam() + ".xml";
    const std::pair<const char*, const char*> baselines[] = {
        {"equiangular=false", "rr_rule=mitsuba"}, {"equiangular=true", "rr_rule=mitsuba"}, {"equiangular=false", "rr_rule=bounded"}};
    for (const auto& [equiangular, rr_rule] : baselines) {
        const std::string out = dir.file(std::string("out-") + equiangular + "-" + rr_rule + ".exr");
        CliResult r = run_cli({"render", scene, "-D", "width=24", "-D", "height=18", "-D", equiangular, "-D", rr_rule,
                               "--spp", "16", "--seed", "1", "--quiet", "-o", out});
        ASSERT_EQ(r.exit_code, 0) << r.err;
        Image img = read_image(out);
        double sum = 0;
        for (const Color3& p : img.pixels) {
            ASSERT_TRUE(p.is_finite());
            sum += p.average();
        }
        EXPECT_GT(sum / double(img.pixels.size()), 1e-4) << GetParam() << ": a black image";
    }
}

INSTANTIATE_TEST_SUITE_P(AllScenes, BenchScene,
                         ::testing::Values("shafts", "backlit", "thin", "sss", "aniso", "cloud", "fogbox", "densesphere",
                                           "glassfog", "skyglobe", "fogcornell", "smoke", "envsss", "door",
                                           "keyhole"));
