#pragma once
// The `to_uv` parameter of textures, a 2-D affine map from the 4x4 XML transform: the upper-left 2x2
// block and the translation column (a `<translate>` shifts the lookup, as Mitsuba 3's render test
// texture_interp shows; releases before 3.6 dropped it), plus the third column, which is where a 3x3
// `<matrix>` puts its 2-D translation.
#include "volguide/core/properties.h"
#include "volguide/core/vec.h"

namespace volguide {

struct UvTransform {
    float m[2][3] = {{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}};

    static UvTransform parse(const Properties& props) {
        UvTransform t;
        if (!props.has("to_uv")) return t;
        const Transform tr = props.get_transform("to_uv");
        const Matrix4& mat = tr.matrix();
        for (int r = 0; r < 2; ++r)
            for (int c = 0; c < 3; ++c) t.m[r][c] = float(mat.m[r][c] + (c == 2 ? mat.m[r][3] : 0.0));
        return t;
    }
    Vec2f apply(const Vec2f& uv) const {
        return {m[0][0] * uv.x + m[0][1] * uv.y + m[0][2], m[1][0] * uv.x + m[1][1] * uv.y + m[1][2]};
    }
};

}  // namespace volguide
