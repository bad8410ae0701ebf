#pragma once
// The fraction of each guiding-field leaf's volume that holds a scattering medium, by jittered
// point sampling (the photon field's fluence is a per-volume collision estimate, which must be
// divided by the medium's share of the leaf: GuidingField::set_medium_fractions).
//
// The medium at a point is found the way a ray would find it: cast from the point in a random
// direction, skip surfaces without media, and at the first shape with media take its interior if
// the ray leaves through it (d . n > 0) and its exterior otherwise; no such shape: the scene's
// ambient medium (ambient_medium: the sensor's only where no shape bounds it — a camera inside a fog
// box does not make the space outside the box foggy). A heterogeneous medium counts only where
// sigma_t > 0.
#include <cstdint>
#include <vector>

#include "volguide/core/ray.h"
#include "volguide/guiding/spatial_tree.h"

namespace volguide {

class Scene;
class Medium;

// The medium at infinity: the sensor's if no shape has it inside (media unbounded around the camera),
// else none.
const Medium* ambient_medium(const Scene& scene);
// The medium at p (nullptr for none), as described above; u picks the probe direction, `ambient` is
// ambient_medium(scene) (computed once by the caller).
const Medium* medium_at(const Scene& scene, const Point3f& p, Point2f u, const Medium* ambient);
// The same rule with the probe along a given ray: the medium a ray leaving from ray.o along ray.d
// travels in first (`ambient` when the probe meets no shape with media).
const Medium* medium_along(const Scene& scene, const Ray& ray, const Medium* ambient);
// The medium enclosing p, from probes along the six axis directions: the first that meets a shape
// with media decides; when all escape, p is outside every shape with media in those directions and
// gets `ambient`.
const Medium* medium_enclosing(const Scene& scene, const Point3f& p, const Medium* ambient);

// The points per leaf guided_volpath measures a field's medium fractions with: ~4 % standard error
// for a half-filled leaf.
inline constexpr int kMediumFractionPoints = 128;

// Per leaf of `tree`: the fraction of `points_per_leaf` jittered points that lie in a medium with
// sigma_t > 0. Parallel over leaves, deterministic for any thread count.
std::vector<float> medium_fractions(const Scene& scene, const SpatialTree& tree, int points_per_leaf, uint64_t seed);

}  // namespace volguide
