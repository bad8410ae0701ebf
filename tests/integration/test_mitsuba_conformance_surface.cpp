// Mitsuba 3 conformance (oracles.md §7) for the surface-only scene of Mitsuba's media test suite.
// Budget: about 2·10^6 samples per scene (spp = 2e6 / pixel count), as Mitsuba's test_renders.
// Needs ../shared/mitsuba-data (third-party data, never copied into the repository): the test is
// skipped, visibly, when that folder is absent; in CI it is always present.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/cli.h"
#include "support/test_support.h"
#include "support/ztest.h"
#include "volguide/render/image_io.h"

using namespace volguide;
using namespace volguide::test;

namespace {

const std::string kSurfaceSuite = shared_dir() + "/mitsuba-data/tests/scenes/participating_media";

void run_surface_conformance(const std::string& name, const std::string& ref_name) {
    if (!std::filesystem::exists(kSurfaceSuite)) GTEST_SKIP() << "SKIPPED: " << kSurfaceSuite << " is absent";
    const std::string scene = kSurfaceSuite + "/" + name + ".xml";
    const std::string ref = kSurfaceSuite + "/refs/" + ref_name + "_ref_rgb.exr";
    const std::string ref_var = kSurfaceSuite + "/refs/" + ref_name + "_ref_rgb_var.exr";
    Image ref_img = read_image(ref), ref_var_img = read_image(ref_var);
    const int spp = int(2e6 / (double(ref_img.width) * ref_img.height) + 0.5);

    TempDir dir("conformance-" + name);
    CliResult r = run_cli({"render", scene, "-o", dir.file("out.exr"), "--spp", std::to_string(spp), "--seed", "1",
                           "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    Image mean = read_image(dir.file("out.exr"));
    Image mask;
    ZTestResult z = pixel_ztest(mean, spp, ref_img, ref_var_img, ZTestOptions{}, &mask);
    if (!z.passed) {
        // Leave the evidence next to the build for inspection.
        std::string stem = std::filesystem::current_path().string() + "/conformance-" + name;
        write_exr(stem + "-render.exr", mean);
        write_exr(stem + "-errors.exr", mask);
    }
    EXPECT_TRUE(z.passed) << name << " at " << spp << " spp: " << z.summary();
}

}  // namespace

TEST(MitsubaConformance, SurfAreaLight) { run_surface_conformance("test_surf_area_light_volpath", "test_surf_area_light"); }
