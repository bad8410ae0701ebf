#pragma once
// Single-precision affine map (3x4 matrix) for hot paths: world <-> volume-local lookups happen
// at every tentative collision, so the double-precision projective Transform is converted once.
#include "volguide/core/transform.h"
#include "volguide/core/vec.h"

namespace volguide {

struct Affine3f {
    float m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

    Affine3f() = default;
    // The upper 3x4 block of a transform (volume transforms are affine).
    explicit Affine3f(const Matrix4& mat) {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) m[r][c] = float(mat.m[r][c]);
    }
    Point3f point(const Point3f& p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    Vec3f vector(const Vec3f& v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
};

}  // namespace volguide
