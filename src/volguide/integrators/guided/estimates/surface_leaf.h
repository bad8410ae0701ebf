#pragma once
// The field's leaf beside a surface vertex, on the side the path arrives from (wi above the shading
// frame: its normal, else the back), looked up a small step (1e-4 of the field's diagonal) off the
// surface: a vertex on a leaf's face finds the leaf on its side of the surface. What the pixel
// estimate reads at a rough surface and the surface direction decision guides with.
#include "volguide/geometry/interaction.h"
#include "volguide/guiding/guiding_field.h"

namespace volguide {

struct SurfaceLeaf {
    Vec3f n;        // the normal of that side
    int leaf = -1;  // -1: none (outside the field, or an empty field)
};
SurfaceLeaf surface_leaf(const GuidingField& field, const SurfaceInteraction& si);

}  // namespace volguide
