#pragma once
// Dense voxel data as read from a file, before it becomes a volume: Mitsuba's binary .vol format
// (media/vol_file.cpp) and OpenVDB grids (media/vdb_file.cpp, the only file including OpenVDB).
#include <string>
#include <vector>

#include "volguide/core/bbox.h"

namespace volguide {

struct GridData {
    int nx = 0, ny = 0, nz = 0;
    int channels = 1;           // 1 (density) or 3 (RGB)
    std::vector<float> values;  // x fastest: values[((z * ny + y) * nx + x) * channels + c]
    BBox3f bbox;                // the file's bounding box (object space), when it has one
    float at(int x, int y, int z, int c = 0) const {
        return values[((size_t(z) * ny + y) * nx + x) * channels + c];
    }
};

// Mitsuba .vol (binary "VOL" version 3, float32 encoding). Throws InputError naming the file.
GridData read_vol_file(const std::string& path);
// Its header only (resolution, channels, bounding box; no values), checked as read_vol_file checks it.
GridData read_vol_header(const std::string& path);
// Writes `grid` as a .vol file (its bbox, or the unit cube when it has none), through a temporary
// file; throws std::runtime_error naming the file on failure.
void write_vol_file(const std::string& path, const GridData& grid);
// One grid of an OpenVDB file, densified over its active bounding box; bbox is its world-space
// extent. Throws InputError naming the file (and the grid when it is missing).
GridData read_vdb_file(const std::string& path, const std::string& grid_name);

}  // namespace volguide
