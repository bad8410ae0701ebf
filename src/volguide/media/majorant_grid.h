#pragma once
// Coarse bounds of sigma_t over the local unit cube of a volume (at most 32^3 cells): per cell
// the scalar majorant (max over channels of sigma_t, for delta/spectral and ratio tracking) and,
// for residual ratio tracking, the per-channel control extinction (the mean of sigma_t over the
// cell's voxels) with the residual rate max_c (max_c - control_c). Where sigma_t < control the
// residual factors exceed 1, which is unbiased; the mean beats the minimum as control because
// cells touching empty space have a zero minimum (bench_media; measured: see bench/RESULTS.md (issue 35)).
// Bounds come from every voxel a lookup inside the cell can read.
#include <vector>

#include "volguide/core/color.h"
#include "volguide/media/voxel_grid.h"

namespace volguide {

struct MajorantCell {
    float majorant = 0.f;       // >= sigma_t,c everywhere in the cell, all channels
    float residual_rate = 0.f;  // >= sigma_t,c - control_c everywhere in the cell
    Color3 control;             // control extinction per channel (cell mean)
};

class MajorantGrid {
public:
    static constexpr int kMaxCells = 32;
    MajorantGrid() = default;
    // Bounds of scale * grid.
    MajorantGrid(const VoxelGrid& grid, float scale);

    int res(int axis) const { return res_[axis]; }
    const int* res() const { return res_; }
    const MajorantCell& cell(int x, int y, int z) const { return cells_[(size_t(z) * res_[1] + y) * res_[0] + x]; }
    float max_majorant() const { return max_majorant_; }

private:
    int res_[3] = {1, 1, 1};
    std::vector<MajorantCell> cells_{1};
    float max_majorant_ = 0.f;
};

}  // namespace volguide
