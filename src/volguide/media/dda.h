#pragma once
// 3-D DDA (Amanatides & Woo) over a grid of cells [0, res)^3: visits, in order, the cells the
// line o + t d crosses for t in [t0, t1], each with its parametric sub-interval.
#include <algorithm>
#include <cmath>

#include "volguide/core/math.h"
#include "volguide/core/vec.h"

namespace volguide {

class GridDda {
public:
    // o, d in cell units (cell i spans [i, i+1) along each axis).
    GridDda(const Point3f& o, const Vec3f& d, const int res[3], float t0, float t1) : t_(t0), t_end_(t1) {
        const Point3f p = o + d * t0;
        for (int a = 0; a < 3; ++a) {
            res_[a] = res[a];
            cell_[a] = std::clamp(int(std::floor(p[a])), 0, res[a] - 1);
            if (d[a] > 0.f) {
                step_[a] = 1;
                t_delta_[a] = 1.f / d[a];
                t_next_[a] = t0 + (float(cell_[a] + 1) - p[a]) / d[a];
            } else if (d[a] < 0.f) {
                step_[a] = -1;
                t_delta_[a] = -1.f / d[a];
                t_next_[a] = t0 + (float(cell_[a]) - p[a]) / d[a];
            } else {
                step_[a] = 0;
                t_delta_[a] = Infinity;
                t_next_[a] = Infinity;
            }
            t_next_[a] = std::max(t_next_[a], t0);
        }
        done_ = !(t0 < t1);
    }

    bool done() const { return done_; }
    float t() const { return t_; }  // start of the current segment
    float segment_end() const { return std::min(t_end_, std::min(t_next_[0], std::min(t_next_[1], t_next_[2]))); }
    int cell(int a) const { return cell_[a]; }

    void advance() {
        const int a = t_next_[0] < t_next_[1] ? (t_next_[0] < t_next_[2] ? 0 : 2) : (t_next_[1] < t_next_[2] ? 1 : 2);
        t_ = t_next_[a];
        if (t_ >= t_end_) {
            done_ = true;
            return;
        }
        cell_[a] += step_[a];
        t_next_[a] += t_delta_[a];
        if (cell_[a] < 0 || cell_[a] >= res_[a]) done_ = true;
    }

private:
    int res_[3], cell_[3], step_[3];
    float t_next_[3], t_delta_[3];
    float t_, t_end_;
    bool done_;
};

}  // namespace volguide
