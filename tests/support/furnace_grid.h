#pragma once
// The chromatic extinction grid of the media furnace tests: sigma_t between about 0.2 and 9 per unit,
// different per channel, over [-1, 1]^3 (8^3 voxels), written as a Mitsuba .vol file.
#include <cmath>
#include <string>

#include "support/cli.h"
#include "support/vol_writer.h"

namespace volguide::test {

inline std::string write_furnace_grid(const TempDir& dir) {
    VolGrid g = make_vol_grid(8, 8, 8, 3, [](float x, float y, float z, int c) {
        const float wave = std::sin(7.f * x + 2.f * c) * std::cos(5.f * y - c) * std::sin(6.f * z + 1.f);
        return 0.1f + 4.5f * (1.f + wave) * (c == 1 ? 0.5f : 1.f);
    });
    const std::string path = dir.file("sigma_t.vol");
    write_vol_file(path, g);
    return path;
}

}  // namespace volguide::test
