#pragma once
// Continuous 2-D distribution on [0,1]^2 whose density is the bilinear interpolation of values
// given on a regular grid of vertices (the same distribution as Mitsuba's Hierarchical2D warp
// without parameters). Sampling picks a cell (row by its marginal, then column), then inverts the
// cell's bilinear density exactly: a linear marginal in y, then a linear conditional in x.
#include <utility>
#include <vector>

#include "volguide/core/distribution.h"
#include "volguide/core/vec.h"

namespace volguide {

class BilinearWarp2D {
  public:
    BilinearWarp2D() = default;
    // `values` holds nx * ny vertex values (row-major, y rows of nx), finite and >= 0; nx, ny >= 2.
    // Vertex (i, j) sits at (i / (nx - 1), j / (ny - 1)). Throws std::invalid_argument on bad input.
    BilinearWarp2D(std::vector<float> values, int nx, int ny);

    // False when every value is zero (nothing can be sampled; pdf is zero everywhere).
    bool valid() const { return norm_ > 0.0; }
    // A point in [0,1)^2 and its density w.r.t. area on the unit square (0 when !valid()).
    std::pair<Point2f, float> sample(Point2f u) const;
    // Density at p in [0,1]^2 (p outside is clamped to the nearest cell).
    float pdf(Point2f p) const;

  private:
    float cell_value(int i, int j, float fx, float fy) const;

    std::vector<float> values_;
    int nx_ = 0, ny_ = 0;
    double norm_ = 0.0;                       // integral of the interpolant over the unit square
    float inv_norm_ = 0.f;                    // 1 / norm_
    DiscreteDistribution rows_;               // cell rows by integral
    std::vector<DiscreteDistribution> cols_;  // cells within each row (empty for rows of zero mass)
};

}  // namespace volguide
