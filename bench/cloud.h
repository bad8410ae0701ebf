#pragma once
// The benchmarks' procedural cloud: blobs modulated by sinusoidal "noise", about 70 % empty,
// density in [0, ~1] (bench_media scales it by 20).
#include <algorithm>
#include <cmath>

#include "volguide/media/grid_data.h"

namespace volguide::bench {

inline GridData cloud_grid(int n) {
    GridData g;
    g.nx = g.ny = g.nz = n;
    g.channels = 1;
    g.values.resize(size_t(n) * n * n);
    const float centres[4][4] = {
        {0.5f, 0.5f, 0.5f, 0.05f}, {0.3f, 0.6f, 0.4f, 0.02f}, {0.7f, 0.4f, 0.6f, 0.03f}, {0.5f, 0.3f, 0.3f, 0.015f}};
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const float u = (x + 0.5f) / n, v = (y + 0.5f) / n, w = (z + 0.5f) / n;
                float d = 0.f;
                for (const auto& c : centres)
                    d += std::exp(-((u - c[0]) * (u - c[0]) + (v - c[1]) * (v - c[1]) + (w - c[2]) * (w - c[2])) / c[3]);
                const float noise = 0.5f + 0.25f * std::sin(23.f * u + 3.f * std::sin(17.f * w)) * std::sin(19.f * v) +
                                    0.25f * std::sin(41.f * w + 5.f * u) * std::cos(37.f * u);
                g.values[(size_t(z) * n + y) * n + x] = std::max(d * noise - 0.3f, 0.f);
            }
    return g;
}

}  // namespace volguide::bench
