// `sdfgrid` (geometry/shapes/sdfgrid.h) against an analytic sphere: the grid holds |p - c| - r at its
// corners; rays from every side must meet it at distance r from c (within the trilinear interpolant's
// error, O(h²)), rays passing beside it must miss, rays from inside must leave through it, and both
// normal modes must point away from c.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/geometry/shapes/sdfgrid.h"

using namespace volguide;

namespace {

constexpr float kSdfRadius = 0.3f;
const Point3f kSdfCenter(0.5f, 0.5f, 0.5f);

SdfValues sdfgrid_sphere_values(int n) {
    SdfValues g{n, n, n, {}};
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const Point3f p(float(x) / float(n - 1), float(y) / float(n - 1), float(z) / float(n - 1));
                g.values.push_back(norm(p - kSdfCenter) - kSdfRadius);
            }
    return g;
}

// The nearest hit over all primitives, as Embree would report it.
bool sdfgrid_nearest(const SdfGrid& grid, const Ray& ray, float& t, uint32_t& prim) {
    t = Infinity;
    for (uint32_t i = 0; i < grid.primitive_count(); ++i) {
        float ti;
        Vec2f uv;
        Ray r = ray;
        r.tmax = std::min(ray.tmax, t);
        if (grid.intersect_primitive(r, i, ti, uv) && ti < t) {
            t = ti;
            prim = i;
        }
    }
    return t < Infinity;
}

}  // namespace

TEST(SdfGrid, RaysMeetTheSphereAtItsRadius) {
    const SdfGrid grid(sdfgrid_sphere_values(33), Transform(), true);
    const float h = 1.f / 32.f;
    Sampler sampler(5, 0, 0);
    for (int i = 0; i < 200; ++i) {
        const Vec3f d = warp::square_to_uniform_sphere(sampler.next_2d());
        // From outside the unit cube towards a point near the centre.
        const Point3f target = kSdfCenter + warp::square_to_uniform_sphere(sampler.next_2d()) * 0.1f;
        const Ray ray(target - d * 2.f, d, Infinity);
        float t;
        uint32_t prim = 0;
        ASSERT_TRUE(sdfgrid_nearest(grid, ray, t, prim)) << i;
        const Point3f p = ray.o + ray.d * t;
        EXPECT_NEAR(norm(p - kSdfCenter), kSdfRadius, h * h) << i;
        // The entry point, not the exit: the ray reaches the sphere before the target point.
        EXPECT_LT(t, 2.f) << i;
        const SurfaceInteraction si = grid.compute_surface_interaction(ray, t, prim, Vec2f(0.f, 0.f));
        const Vec3f radial = normalize(p - kSdfCenter);
        EXPECT_GT(dot(si.n, radial), 0.995f) << i;
        EXPECT_GT(dot(si.sh_frame.n, radial), 0.995f) << i;
    }
}

TEST(SdfGrid, RaysBesideTheSphereMissAndRaysFromInsideLeave) {
    const SdfGrid grid(sdfgrid_sphere_values(33), Transform(), false);
    float t;
    uint32_t prim;
    // Passing at distance 0.33 > r from the centre.
    EXPECT_FALSE(sdfgrid_nearest(grid, Ray(Point3f(-1.f, 0.83f, 0.5f), Vec3f(1, 0, 0), Infinity), t, prim));
    // Stopping short of the sphere.
    EXPECT_FALSE(sdfgrid_nearest(grid, Ray(Point3f(-1.f, 0.5f, 0.5f), Vec3f(1, 0, 0), 1.1f), t, prim));
    // From the centre outwards: the exit at r.
    ASSERT_TRUE(sdfgrid_nearest(grid, Ray(kSdfCenter, normalize(Vec3f(1, 2, 3)), Infinity), t, prim));
    EXPECT_NEAR(t, kSdfRadius, 1e-3f);
    // A non-unit direction keeps the ray's parameter: twice the direction, half the distance.
    ASSERT_TRUE(sdfgrid_nearest(grid, Ray(Point3f(-1.f, 0.5f, 0.5f), Vec3f(2, 0, 0), Infinity), t, prim));
    EXPECT_NEAR(t, (1.5f - kSdfRadius) / 2.f, 1e-3f);
}

TEST(SdfGrid, PlacedByToWorldAndValuesAtCorners) {
    const Transform to_world = Transform::translate(Vec3f(2.f, 0.f, 0.f)) * Transform::scale(Vec3f(4.f));
    const SdfGrid grid(sdfgrid_sphere_values(17), to_world, true);
    EXPECT_FLOAT_EQ(grid.value(Point3f(0.5f, 0.5f, 0.5f)), -kSdfRadius);
    EXPECT_FLOAT_EQ(grid.value(Point3f(0.f, 0.f, 0.f)), norm(Vec3f(0.5f)) - kSdfRadius);
    float t;
    uint32_t prim;
    // World sphere: centre (4, 2, 2), radius 1.2.
    ASSERT_TRUE(sdfgrid_nearest(grid, Ray(Point3f(4.f, 2.f, -5.f), Vec3f(0, 0, 1), Infinity), t, prim));
    EXPECT_NEAR(t, 7.f - 4.f * kSdfRadius, 4e-2f);
    const BBox3f b = grid.bbox();
    EXPECT_FLOAT_EQ(b.lo.x, 2.f);
    EXPECT_FLOAT_EQ(b.hi.x, 6.f);
}

TEST(SdfGrid, RejectsGridsWithoutSurface) {
    SdfValues g{2, 2, 2, std::vector<float>(8, 1.f)};
    EXPECT_THROW(SdfGrid(g, Transform(), true), std::invalid_argument);
    g.values.resize(7);
    EXPECT_THROW(SdfGrid(g, Transform(), true), std::invalid_argument);
}

// One voxel whose interpolant meets a diagonal ray twice: corners (0,0,0) and (1,1,1) at +1, the rest at
// -1, so along x = y = z = s it is 1 - 6s + 6s², roots s = (3 ∓ √3) / 6. The first must be found, not
// the second (the derivative's root s = 1/2 lies between them).
TEST(SdfGrid, FirstOfTwoRootsInOneVoxel) {
    SdfValues g{2, 2, 2, {1.f, -1.f, -1.f, -1.f, -1.f, -1.f, -1.f, 1.f}};
    const SdfGrid grid(g, Transform(), false);
    float t;
    uint32_t prim;
    ASSERT_TRUE(sdfgrid_nearest(grid, Ray(Point3f(-1.f), Vec3f(1.f), Infinity), t, prim));
    EXPECT_NEAR(t, 1.f + (3.f - std::sqrt(3.f)) / 6.f, 1e-4f);
    // From inside the first region (s = 0.5, where the value is -0.5) forward: the second root.
    ASSERT_TRUE(sdfgrid_nearest(grid, Ray(Point3f(0.5f), Vec3f(1.f), Infinity), t, prim));
    EXPECT_NEAR(t, (3.f + std::sqrt(3.f)) / 6.f - 0.5f, 1e-4f);
}
