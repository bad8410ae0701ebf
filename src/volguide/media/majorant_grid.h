#pragma once
// Coarse bounds of sigma_t over the local unit cube of a volume (at most 32^3 cells): per cell
// the scalar majorant (max over channels of sigma_t, for delta/spectral and ratio tracking) and,
// for residual ratio tracking, the per-channel control (min of sigma_t) with the residual rate
// max_c (max_c - min_c). Bounds come from every voxel a lookup inside the cell can read.
#include <vector>

#include "volguide/core/color.h"
#include "volguide/media/voxel_grid.h"

namespace volguide {

struct MajorantCell {
    float majorant = 0.f;       // >= sigma_t,c everywhere in the cell, all channels
    float residual_rate = 0.f;  // >= sigma_t,c - control_c everywhere in the cell
    Color3 control;             // <= sigma_t,c everywhere in the cell
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
