#pragma once
// A dense grid of 1- or 3-channel values over the local unit cube [0,1]^3, looked up with
// Mitsuba 3's (Dr.Jit texture) conventions: voxel i covers [i/res, (i+1)/res] and its value sits
// at the centre (i + 0.5)/res; trilinear filtering interpolates between centres, nearest takes the
// voxel containing the point; indices outside the grid are clamped, repeated or mirrored.
// A constant value is a 1x1x1 grid. Value type: media look voxels up without virtual calls.
#include <vector>

#include "volguide/core/color.h"
#include "volguide/core/vec.h"
#include "volguide/media/grid_data.h"

namespace volguide {

enum class VolumeFilter { Trilinear, Nearest };
enum class VolumeWrap { Clamp, Repeat, Mirror };

class VoxelGrid {
public:
    VoxelGrid() : VoxelGrid(Color3(0.f)) {}
    explicit VoxelGrid(const Color3& constant);
    // data.values must hold nx * ny * nz * channels values (channels 1 or 3).
    VoxelGrid(const GridData& data, VolumeFilter filter, VolumeWrap wrap);

    // Value at a point of local (unit cube) coordinates.
    Color3 lookup(const Point3f& u) const {
        return filter_ == VolumeFilter::Trilinear ? lookup_trilinear(u) : lookup_nearest(u);
    }

    int res(int axis) const { return res_[axis]; }
    int channels() const { return channels_; }
    float max_value() const { return max_value_; }  // over all voxels and channels
    float min_value() const { return min_value_; }
    bool is_constant() const { return res_[0] == 1 && res_[1] == 1 && res_[2] == 1; }
    VolumeFilter filter() const { return filter_; }

    // Per-channel min and max over the voxels that lookups anywhere in the local box [lo, hi]
    // can read (both filters), with one voxel of margin against rounding at the box faces.
    // Also their per-channel mean.
    void range(const Point3f& lo, const Point3f& hi, Color3& mn, Color3& mx, Color3& mean) const;

private:
    int wrap(int i, int axis) const;
    Color3 voxel(int x, int y, int z) const {
        const size_t i = (size_t(z) * res_[1] + y) * res_[0] + x;
        if (channels_ == 1) return Color3(values_[i]);
        return {values_[3 * i], values_[3 * i + 1], values_[3 * i + 2]};
    }
    Color3 lookup_trilinear(const Point3f& u) const;
    Color3 lookup_nearest(const Point3f& u) const;

    int res_[3] = {1, 1, 1};
    int channels_ = 1;
    std::vector<float> values_;
    VolumeFilter filter_ = VolumeFilter::Trilinear;
    VolumeWrap wrap_ = VolumeWrap::Clamp;
    float max_value_ = 0.f, min_value_ = 0.f;
};

}  // namespace volguide
