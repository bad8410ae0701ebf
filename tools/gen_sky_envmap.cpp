// Writes the held-out benchmark scene `envsss`'s environment map (bench/scenes/envsss.xml): an
// equirectangular sky as Mitsuba's `envmap` reads it (+Y up, the image's top row the zenith), width x
// width/2 pixels: a horizon-to-zenith gradient, a darker ground below the horizon and a small bright sun
// (3 degrees across, 35 degrees up) — light from everywhere and one strong direction. Deterministic.
// Regenerate with
//   cmake --build build --target gen_sky_envmap && build/gen_sky_envmap 256 bench/scenes/sky.exr
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "volguide/core/image.h"
#include "volguide/core/math.h"
#include "volguide/render/image_io.h"

namespace {

volguide::Color3 sky(float theta, float phi) {
    using volguide::Color3;
    const float elevation = 0.5f * volguide::Pi - theta;  // radians above the horizon
    const float sun_elevation = 35.f * volguide::Pi / 180.f, sun_phi = 1.1f;
    const float cos_to_sun = std::sin(elevation) * std::sin(sun_elevation) +
                             std::cos(elevation) * std::cos(sun_elevation) * std::cos(phi - sun_phi);
    if (cos_to_sun > std::cos(1.5f * volguide::Pi / 180.f)) return Color3(900.f, 820.f, 700.f);
    if (elevation < 0.f) return Color3(0.12f, 0.10f, 0.08f);  // the ground
    const float t = std::pow(std::sin(elevation), 0.4f);
    const Color3 horizon(1.0f, 0.95f, 0.9f), zenith(0.25f, 0.45f, 0.95f);
    const float glow = 0.6f * std::pow(std::max(0.f, cos_to_sun), 8.f);
    return horizon * (1.f - t) + zenith * t + Color3(glow, 0.8f * glow, 0.5f * glow);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: gen_sky_envmap WIDTH OUT.exr\n");
        return 2;
    }
    const int w = std::atoi(argv[1]);
    if (w < 8 || w > 8192 || w % 2) {
        std::fprintf(stderr, "gen_sky_envmap: width must be even and in [8, 8192]\n");
        return 2;
    }
    try {
        volguide::Image image(w, w / 2);
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x) {
                const float theta = (y + 0.5f) / float(image.height) * volguide::Pi;
                const float phi = (x + 0.5f) / float(image.width) * 2.f * volguide::Pi;
                image.pixels[size_t(y) * size_t(image.width) + size_t(x)] = sky(theta, phi);
            }
        volguide::write_exr(argv[2], image);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gen_sky_envmap: %s\n", e.what());
        return 1;
    }
    std::printf("wrote %s (%d x %d)\n", argv[2], w, w / 2);
    return 0;
}
