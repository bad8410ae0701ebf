// Camera conventions end to end: a Mitsuba 3 test scene rendered through load_scene + render() must
// match Mitsuba's reference image far better than the same reference mirrored in x or in y (a
// handedness or y-flip bug in the camera or the film would swap that ordering).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "support/test_support.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/render/image_compare.h"
#include "volguide/render/image_io.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

namespace volguide {
namespace {

Image mirrored(const Image& img, bool in_x) {
    Image out(img.width, img.height);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            out.at(x, y) = in_x ? img.at(img.width - 1 - x, y) : img.at(x, img.height - 1 - y);
    return out;
}

TEST(RenderOrientation, MatchesMitsubaNotItsMirror) {
    const std::string dir = test::shared_dir() + "/mitsuba-data/tests/scenes/participating_media";
    const std::string scene_file = dir + "/test_surf_area_light_volpath.xml";
    if (!std::filesystem::exists(scene_file)) GTEST_SKIP() << "Mitsuba test data not available";
    auto scene = load_scene(scene_file);
    RenderOptions options;
    options.spp = 32;
    options.seed = 1;
    RenderResult r = render(*scene, options);
    Image ref = read_image(dir + "/refs/test_surf_area_light_ref_rgb.exr");
    ASSERT_EQ(r.mean.width, ref.width);
    ASSERT_EQ(r.mean.height, ref.height);
    const double direct = compare_images(r.mean, ref).mse;
    const double flip_x = compare_images(r.mean, mirrored(ref, true)).mse;
    const double flip_y = compare_images(r.mean, mirrored(ref, false)).mse;
    std::printf("mse direct %g, mirrored x %g, y %g\n", direct, flip_x, flip_y);
    EXPECT_LT(3 * direct, flip_x) << "direct " << direct << " mirrored in x " << flip_x;
    EXPECT_LT(3 * direct, flip_y) << "direct " << direct << " mirrored in y " << flip_y;
}

}  // namespace
}  // namespace volguide
