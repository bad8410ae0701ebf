#pragma once
// Completes a SurfaceInteraction the way Mitsuba 3 does after a shape filled p, n, sh_frame.n,
// uv and dp_du: the shading frame's tangent is dp_du made orthogonal to the shading normal
// (Gram-Schmidt), falling back to an arbitrary tangent when dp_du is degenerate; wi is -ray.d
// in that frame.
#include "volguide/core/frame.h"
#include "volguide/core/ray.h"
#include "volguide/geometry/interaction.h"

namespace volguide {

inline void finalize_shading_frame(SurfaceInteraction& si, const Ray& ray) {
    const Vec3f& n = si.sh_frame.n;
    Vec3f s = si.dp_du - n * dot(n, si.dp_du);
    float len2 = squared_norm(s);
    if (len2 > 1e-20f * std::max(squared_norm(si.dp_du), 1e-30f) && std::isfinite(len2)) {
        s = s / std::sqrt(len2);
        si.sh_frame.s = s;
        si.sh_frame.t = cross(n, s);
    } else {
        coordinate_system(n, si.sh_frame.s, si.sh_frame.t);
    }
    si.wi = si.sh_frame.to_local(-ray.d);
}

}  // namespace volguide
