// Writes the held-out benchmark scene `smoke`'s density (bench/scenes/smoke.xml): a rising column of
// smoke, a Mitsuba .vol grid of nx x 2nx x nx voxels over the unit cube. The column is a tube whose radius
// grows with height and whose axis wanders, its density falling off from the axis and thinned by a
// deterministic sum of sines (no random numbers: the same file on every machine). Regenerate with
//   cmake --build build --target gen_smoke_vol && build/gen_smoke_vol 32 bench/scenes/smoke.vol
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "volguide/media/grid_data.h"

namespace {

float smoke_density(float u, float v, float w) {
    // v: height in [0, 1]. The axis drifts and the tube widens as the smoke rises.
    const float cx = 0.5f + 0.12f * std::sin(5.f * v) + 0.05f * std::sin(13.f * v + 1.f);
    const float cz = 0.5f + 0.10f * std::cos(4.f * v + 0.5f);
    const float radius = 0.08f + 0.22f * v;
    const float r = std::hypot(u - cx, w - cz) / radius;
    const float core = std::exp(-2.5f * r * r);
    const float wisps = 0.55f + 0.3f * std::sin(31.f * v + 7.f * u) * std::cos(23.f * w + 5.f * v) +
                        0.15f * std::sin(53.f * u + 41.f * w + 17.f * v);
    const float fade = std::clamp(6.f * v, 0.f, 1.f) * std::clamp(5.f * (1.f - v), 0.f, 1.f);
    return std::max(0.f, core * wisps * fade - 0.05f);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: gen_smoke_vol RESOLUTION OUT.vol\n");
        return 2;
    }
    const int n = std::atoi(argv[1]);
    if (n < 2 || n > 256) {
        std::fprintf(stderr, "gen_smoke_vol: resolution must be in [2, 256]\n");
        return 2;
    }
    try {
        volguide::GridData g;
        g.nx = g.nz = n;
        g.ny = 2 * n;
        g.channels = 1;
        g.values.resize(size_t(g.nx) * size_t(g.ny) * size_t(g.nz));
        for (int z = 0; z < g.nz; ++z)
            for (int y = 0; y < g.ny; ++y)
                for (int x = 0; x < g.nx; ++x)
                    g.values[(size_t(z) * size_t(g.ny) + size_t(y)) * size_t(g.nx) + size_t(x)] =
                        smoke_density((x + 0.5f) / float(g.nx), (y + 0.5f) / float(g.ny), (z + 0.5f) / float(g.nz));
        g.bbox = volguide::BBox3f(volguide::Point3f(0.f), volguide::Point3f(1.f));
        volguide::write_vol_file(argv[2], g);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gen_smoke_vol: %s\n", e.what());
        return 1;
    }
    std::printf("wrote %s (%d x %d x %d voxels)\n", argv[2], n, 2 * n, n);
    return 0;
}
