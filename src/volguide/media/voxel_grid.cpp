#include "volguide/media/voxel_grid.h"

#include <cmath>

namespace volguide {

VoxelGrid::VoxelGrid(const Color3& c) : channels_(3), values_{c.r, c.g, c.b} {
    max_value_ = c.max_value();
    min_value_ = c.min_value();
}

VoxelGrid::VoxelGrid(const GridData& data, VolumeFilter filter, VolumeWrap wrap)
    : res_{data.nx, data.ny, data.nz}, channels_(data.channels), values_(data.values), filter_(filter), wrap_(wrap) {
    max_value_ = -Infinity;
    min_value_ = Infinity;
    for (float v : values_) {
        max_value_ = std::max(max_value_, v);
        min_value_ = std::min(min_value_, v);
    }
}

int VoxelGrid::wrap(int i, int axis) const {
    const int n = res_[axis];
    switch (wrap_) {
        case VolumeWrap::Clamp: return std::clamp(i, 0, n - 1);
        case VolumeWrap::Repeat: {
            int m = i % n;
            return m < 0 ? m + n : m;
        }
        case VolumeWrap::Mirror: {
            int m = i % (2 * n);
            if (m < 0) m += 2 * n;
            return m < n ? m : 2 * n - 1 - m;
        }
    }
    return 0;
}

// Coordinates far outside the grid (or NaN) are clamped before the float -> int conversion.
static inline float safe_coord(float x) { return std::isnan(x) ? 0.f : std::clamp(x, -1e7f, 1e7f); }

Color3 VoxelGrid::lookup_trilinear(const Point3f& u) const {
    const float px = safe_coord(u.x * res_[0] - 0.5f), py = safe_coord(u.y * res_[1] - 0.5f),
                pz = safe_coord(u.z * res_[2] - 0.5f);
    const float fx0 = std::floor(px), fy0 = std::floor(py), fz0 = std::floor(pz);
    const float wx = px - fx0, wy = py - fy0, wz = pz - fz0;
    const int ix = int(fx0), iy = int(fy0), iz = int(fz0);
    const int x0 = wrap(ix, 0), x1 = wrap(ix + 1, 0), y0 = wrap(iy, 1), y1 = wrap(iy + 1, 1), z0 = wrap(iz, 2),
              z1 = wrap(iz + 1, 2);
    const Color3 c00 = lerp(wx, voxel(x0, y0, z0), voxel(x1, y0, z0));
    const Color3 c10 = lerp(wx, voxel(x0, y1, z0), voxel(x1, y1, z0));
    const Color3 c01 = lerp(wx, voxel(x0, y0, z1), voxel(x1, y0, z1));
    const Color3 c11 = lerp(wx, voxel(x0, y1, z1), voxel(x1, y1, z1));
    return lerp(wz, lerp(wy, c00, c10), lerp(wy, c01, c11));
}

Color3 VoxelGrid::lookup_nearest(const Point3f& u) const {
    const int x = wrap(int(std::floor(safe_coord(u.x * res_[0]))), 0);
    const int y = wrap(int(std::floor(safe_coord(u.y * res_[1]))), 1);
    const int z = wrap(int(std::floor(safe_coord(u.z * res_[2]))), 2);
    return voxel(x, y, z);
}

void VoxelGrid::range(const Point3f& lo, const Point3f& hi, Color3& mn, Color3& mx, Color3& mean) const {
    int first[3], last[3];
    for (int a = 0; a < 3; ++a) {
        // Trilinear reads floor(u res - 0.5) and the next voxel; nearest reads floor(u res),
        // which lies within that pair. One more voxel on each side absorbs rounding.
        first[a] = int(std::floor(safe_coord(lo[a] * res_[a] - 0.5f))) - 1;
        last[a] = int(std::floor(safe_coord(hi[a] * res_[a] - 0.5f))) + 2;
        if (wrap_ == VolumeWrap::Clamp || last[a] - first[a] + 1 >= res_[a] + 2) {
            // Clamped indices; a range wider than the grid covers every voxel in any mode.
            if (wrap_ != VolumeWrap::Clamp) first[a] = 0, last[a] = res_[a] - 1;
            first[a] = std::clamp(first[a], 0, res_[a] - 1);
            last[a] = std::clamp(last[a], 0, res_[a] - 1);
        }
    }
    mn = Color3(Infinity);
    mx = Color3(-Infinity);
    Color3 sum(0.f);
    int count = 0;
    for (int z = first[2]; z <= last[2]; ++z)
        for (int y = first[1]; y <= last[1]; ++y)
            for (int x = first[0]; x <= last[0]; ++x) {
                const Color3 v = voxel(wrap(x, 0), wrap(y, 1), wrap(z, 2));
                sum += v;
                ++count;
                for (int c = 0; c < 3; ++c) {
                    mn[c] = std::min(mn[c], v[c]);
                    mx[c] = std::max(mx[c], v[c]);
                }
            }
    mean = sum / float(std::max(count, 1));
}

}  // namespace volguide
