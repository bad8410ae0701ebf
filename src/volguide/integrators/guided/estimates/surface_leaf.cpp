#include "volguide/integrators/guided/estimates/surface_leaf.h"

namespace volguide {

SurfaceLeaf surface_leaf(const GuidingField& field, const SurfaceInteraction& si) {
    SurfaceLeaf s;
    s.n = si.wi.z >= 0.f ? Vec3f(si.sh_frame.n) : -Vec3f(si.sh_frame.n);
    if (!field.empty()) s.leaf = field.tree().leaf_at(si.p + s.n * (1e-4f * norm(field.tree().bounds().extents())));
    return s;
}

}  // namespace volguide
