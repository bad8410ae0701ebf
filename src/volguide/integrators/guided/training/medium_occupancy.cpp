#include "volguide/integrators/guided/training/medium_occupancy.h"

#include <optional>

#include "volguide/core/parallel.h"
#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/media/medium.h"
#include "volguide/render/scene.h"

namespace volguide {

namespace {
constexpr uint64_t kOccupancyStream = 0x0CC0BA7Cull;
constexpr int kMaxSkippedSurfaces = 64;
}  // namespace

const Medium* medium_at(const Scene& scene, const Point3f& p, Point2f u, const Medium* ambient) {
    return medium_along(scene, Ray(p, warp::square_to_uniform_sphere(u)), ambient);
}

namespace {
// The medium on the near side of the first shape with media along the probe; none: nullopt.
std::optional<const Medium*> medium_hit_along(const Scene& scene, const Ray& probe) {
    Ray ray = probe;
    for (int k = 0; k < kMaxSkippedSurfaces; ++k) {
        SurfaceInteraction si;
        if (!scene.intersect(ray, si)) break;
        const Shape& shape = *si.shape;
        if (shape.interior_medium() || shape.exterior_medium())
            return dot(ray.d, si.n) > 0.f ? shape.interior_medium() : shape.exterior_medium();
        ray = si.spawn_ray(ray.d);
    }
    return std::nullopt;
}
}  // namespace

const Medium* medium_along(const Scene& scene, const Ray& probe, const Medium* ambient) {
    return medium_hit_along(scene, probe).value_or(ambient);
}

const Medium* ambient_medium(const Scene& scene) {
    const Medium* sensor = scene.sensor().medium();
    if (!sensor) return nullptr;
    for (const auto& shape : scene.shapes())
        if (shape->interior_medium() == sensor) return nullptr;
    return sensor;
}

const Medium* medium_enclosing(const Scene& scene, const Point3f& p, const Medium* ambient) {
    for (int a = 0; a < 6; ++a) {
        Vec3f d(0.f);
        d[a / 2] = a % 2 ? -1.f : 1.f;
        if (const std::optional<const Medium*> m = medium_hit_along(scene, Ray(p, d))) return *m;
    }
    return ambient;  // every probe escaped: p sees infinity
}

std::vector<float> medium_fractions(const Scene& scene, const SpatialTree& tree, int points_per_leaf, uint64_t seed) {
    std::vector<float> fractions(size_t(tree.leaf_count()), 0.f);
    const int n = std::max(points_per_leaf, 1);
    const Medium* ambient = ambient_medium(scene);
    parallel_for(0, tree.leaf_count(), [&](int leaf) {
        const BBox3f& b = tree.leaf_bounds(leaf);
        Sampler sampler(seed, kOccupancyStream, uint64_t(leaf));
        int inside = 0;
        for (int i = 0; i < n; ++i) {
            const Vec3f e = b.extents();
            const Point3f p(b.lo.x + e.x * sampler.next_1d(), b.lo.y + e.y * sampler.next_1d(),
                            b.lo.z + e.z * sampler.next_1d());
            const Medium* m = medium_at(scene, p, sampler.next_2d(), ambient);
            if (m && m->eval(p).sigma_t.max_value() > 0.f) ++inside;
        }
        fractions[size_t(leaf)] = float(inside) / float(n);
    });
    return fractions;
}

}  // namespace volguide
