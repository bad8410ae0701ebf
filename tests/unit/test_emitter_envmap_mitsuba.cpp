// Envmap conformance with Mitsuba 3's own reference image: in test_homo_dielectric_envmap the
// image's left and right borders see museum.exr directly. Each such pixel is the box-filtered
// radiance over the pixel footprint, which we integrate with a small pinhole model of Mitsuba's
// default perspective sensor (focal_length 50mm on a 36x24 film, i.e. fov_axis "diagonal"),
// independent of volguide's sensor module. A half-texel error in the map's orientation is 10x
// larger than the tolerance (checked below).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "support/emitter_test_util.h"
#include "support/test_support.h"
#include "volguide/core/transform.h"

using namespace volguide;
using namespace volguide::test;

namespace {

struct Strip {
    double rms = 0.0;    // root-mean-square difference to the reference
    double worst = 0.0;  // largest relative difference of one pixel-channel
};

// Compares the reference's border columns (rows 0..29, above the spheres) with the envmap seen
// through the sensor; `du` rotates the map by that fraction of a turn (0 = as implemented).
Strip compare_border(const Emitter& env, const Image& ref, float du) {
    const Transform cam = Transform::look_at({0.f, 0.5f, 4.f}, {0.f, -0.5f, 0.f}, {0.f, 1.f, 0.f});
    // Mitsuba's default: diagonal fov of a 50 mm lens on 36x24 film; square image.
    const float tan_half_x = float(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / 100.0 / std::sqrt(2.0));
    const int w = ref.width, h = ref.height, s = 12;
    Strip out;
    int n = 0;
    for (int y = 0; y < 30; ++y)
        for (int x : {0, 1, 2, w - 3, w - 2, w - 1}) {
            Color3 sum(0.f);
            for (int sy = 0; sy < s; ++sy)
                for (int sx = 0; sx < s; ++sx) {
                    const float u = (x + (sx + 0.5f) / s) / w, v = (y + (sy + 0.5f) / s) / h;
                    // Camera space: +x is left, +y up, +z forward (Mitsuba's look_at).
                    const Vec3f dc((1.f - 2.f * u) * tan_half_x, (1.f - 2.f * v) * tan_half_x, 1.f);
                    Vec3f d = normalize(cam.apply_vector(normalize(dc)));
                    if (du != 0.f) {
                        const float theta = safe_acos(d.y), phi = std::atan2(d.x, -d.z) + 2.f * Pi * du;
                        d = {std::sin(phi) * std::sin(theta), std::cos(theta),
                             -std::cos(phi) * std::sin(theta)};
                    }
                    sum += env.eval(escaped_ray(d));
                }
            const Color3 mine = sum / float(s * s), theirs = ref.at(x, y);
            for (int c = 0; c < 3; ++c) {
                out.rms += sqr(double(mine[c] - theirs[c]));
                out.worst = std::max(
                    out.worst, std::abs(double(mine[c] - theirs[c])) / std::max(0.05, double(theirs[c])));
                ++n;
            }
        }
    out.rms = std::sqrt(out.rms / n);
    return out;
}

}  // namespace

TEST(EnvmapMitsubaConformance, BorderPixelsOfDielectricEnvmapReference) {
    const std::string data = shared_dir() + "/mitsuba-data";
    const std::string ref_file =
        data + "/tests/scenes/participating_media/refs/test_homo_dielectric_envmap_ref_rgb.exr";
    const std::string map_file = data + "/common/textures/museum.exr";
    if (!std::filesystem::exists(ref_file) || !std::filesystem::exists(map_file))
        GTEST_SKIP() << "missing Mitsuba test data under " << data;
    const Image ref = read_image(ref_file);
    ASSERT_EQ(ref.width, 48);
    auto env = EmitterBuilder("envmap").set("filename", map_file).build();

    const Strip exact = compare_border(*env, ref, 0.f);
    EXPECT_LT(exact.rms, 0.01) << "worst relative error " << exact.worst;
    EXPECT_LT(exact.worst, 0.03);
    // Power check: the same comparison with the map turned by half a texel clearly fails.
    const Strip shifted = compare_border(*env, ref, 0.5f / 512.f);
    EXPECT_GT(shifted.rms, 10.0 * exact.rms);
    std::printf("border pixels: rms %.5f (worst relative %.4f); half-texel rotated map: rms %.5f\n",
                exact.rms, exact.worst, shifted.rms);
}
