#pragma once
// Writes Mitsuba .vol grids (binary "VOL", version 3, float32, x fastest) for tests, plus
// deliberately broken variants for the error tests.
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace volguide::test {

struct VolGrid {
    int nx = 1, ny = 1, nz = 1, channels = 1;
    float bbox[6] = {0, 0, 0, 1, 1, 1};  // xmin ymin zmin xmax ymax zmax
    std::vector<float> values;            // ((z * ny + y) * nx + x) * channels + c
};

// Fills values from f(x, y, z, c), evaluated at voxel centres in the unit cube:
// ((i + 0.5) / n) along each axis (Mitsuba's convention).
inline VolGrid make_vol_grid(int nx, int ny, int nz, int channels,
                             const std::function<float(float, float, float, int)>& f) {
    VolGrid g;
    g.nx = nx, g.ny = ny, g.nz = nz, g.channels = channels;
    g.values.resize(size_t(nx) * ny * nz * channels);
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x)
                for (int c = 0; c < channels; ++c)
                    g.values[((size_t(z) * ny + y) * nx + x) * channels + c] =
                        f((x + 0.5f) / nx, (y + 0.5f) / ny, (z + 0.5f) / nz, c);
    return g;
}

// `magic` and `version` let tests write invalid headers; `truncate_bytes` drops the file's tail.
inline void write_vol_file(const std::string& path, const VolGrid& g, const char* magic = "VOL", int version = 3,
                           int encoding = 1, size_t truncate_bytes = 0) {
    std::vector<char> bytes;
    auto put = [&](const void* p, size_t n) {
        const char* c = static_cast<const char*>(p);
        bytes.insert(bytes.end(), c, c + n);
    };
    put(magic, 3);
    const uint8_t v = uint8_t(version);
    put(&v, 1);
    const int32_t ints[5] = {encoding, g.nx, g.ny, g.nz, g.channels};
    put(ints, sizeof(ints));
    put(g.bbox, sizeof(g.bbox));
    put(g.values.data(), g.values.size() * sizeof(float));
    bytes.resize(bytes.size() - std::min(truncate_bytes, bytes.size()));
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

}  // namespace volguide::test
