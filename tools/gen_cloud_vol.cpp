// Writes the procedural cloud of the benchmarks (bench/cloud.h) as a Mitsuba .vol grid.
// Regenerate the committed bench asset with:
//   cmake --build build --target gen_cloud_vol && build/gen_cloud_vol 40 bench/scenes/cloud.vol
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "../bench/cloud.h"

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: gen_cloud_vol RESOLUTION OUT.vol\n");
        return 2;
    }
    const int n = std::atoi(argv[1]);
    if (n < 2 || n > 512) {
        std::fprintf(stderr, "gen_cloud_vol: resolution must be in [2, 512]\n");
        return 2;
    }
    try {
        volguide::GridData g = volguide::bench::cloud_grid(n);
        g.bbox = volguide::BBox3f(volguide::Point3f(0.f), volguide::Point3f(1.f));
        volguide::write_vol_file(argv[2], g);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gen_cloud_vol: %s\n", e.what());
        return 1;
    }
    std::printf("wrote %s (%d^3 voxels)\n", argv[2], n);
    return 0;
}
