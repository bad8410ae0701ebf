#include "volguide/media/majorant_grid.h"

namespace volguide {

MajorantGrid::MajorantGrid(const VoxelGrid& grid, float scale) {
    for (int a = 0; a < 3; ++a) res_[a] = std::min(grid.res(a), kMaxCells);
    cells_.assign(size_t(res_[0]) * res_[1] * res_[2], MajorantCell{});
    max_majorant_ = 0.f;
    for (int z = 0; z < res_[2]; ++z)
        for (int y = 0; y < res_[1]; ++y)
            for (int x = 0; x < res_[0]; ++x) {
                const Point3f lo(float(x) / res_[0], float(y) / res_[1], float(z) / res_[2]);
                const Point3f hi(float(x + 1) / res_[0], float(y + 1) / res_[1], float(z + 1) / res_[2]);
                Color3 mn, mx, mean;
                grid.range(lo, hi, mn, mx, mean);
                MajorantCell& c = cells_[(size_t(z) * res_[1] + y) * res_[0] + x];
                c.majorant = scale * mx.max_value();
                c.control = mean * scale;
                c.residual_rate = std::max({scale * mx.r - c.control.r, scale * mx.g - c.control.g,
                                            scale * mx.b - c.control.b, 0.f});
                max_majorant_ = std::max(max_majorant_, c.majorant);
            }
}

}  // namespace volguide
