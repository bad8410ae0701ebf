// Accel (Embree): closest hits across triangle meshes and analytic shapes, tmax, occlusion,
// the empty scene, and agreement between threads.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>

#include "test_shape_util.h"
#include "volguide/geometry/accel.h"

using namespace volguide;
using namespace volguide::test;

namespace {

struct Scene3 {
    std::shared_ptr<Shape> floor, sphere, disk;
    std::unique_ptr<Accel> accel;
    Scene3() {
        // Floor: rectangle scaled to [-10,10]^2 at z=0; unit sphere at z=2; disk at z=5 facing down.
        floor = make_shape(ShapeProps("rectangle").t("to_world", Transform::scale({10, 10, 1})));
        sphere = make_shape(ShapeProps("sphere").p("center", {0, 0, 2}));
        disk = make_shape(
            ShapeProps("disk").t("to_world", Transform::translate({3, 0, 5})).b("flip_normals", true));
        accel = std::make_unique<Accel>(std::vector<const Shape*>{floor.get(), sphere.get(), disk.get()});
    }
};

}  // namespace

TEST(Accel, ClosestHitAcrossShapeKinds) {
    Scene3 s;
    SurfaceInteraction si;
    ASSERT_TRUE(s.accel->intersect(Ray({0, 0, 10}, {0, 0, -1}), si));
    EXPECT_EQ(si.shape, s.sphere.get());
    EXPECT_NEAR(si.t, 7.f, 1e-5f);
    EXPECT_NEAR(si.n.z, 1.f, 1e-5f);

    ASSERT_TRUE(s.accel->intersect(Ray({5, 5, 10}, {0, 0, -1}), si));
    EXPECT_EQ(si.shape, s.floor.get());
    EXPECT_NEAR(si.t, 10.f, 1e-5f);
    EXPECT_NEAR(si.p.x, 5.f, 1e-5f);
    EXPECT_NEAR(si.uv.x, 0.75f, 1e-5f);  // rectangle uv = (x+1)/2 in object space
    EXPECT_NEAR(si.uv.y, 0.75f, 1e-5f);
    EXPECT_NEAR(si.wi.z, 1.f, 1e-5f);

    ASSERT_TRUE(s.accel->intersect(Ray({3, 0, 10}, {0, 0, -1}), si));
    EXPECT_EQ(si.shape, s.disk.get());
    EXPECT_NEAR(si.t, 5.f, 1e-5f);
    EXPECT_NEAR(si.n.z, -1.f, 1e-5f);
    EXPECT_LT(si.wi.z, 0.f);  // seen from its back

    // From inside the sphere, upwards: the far side of the sphere.
    ASSERT_TRUE(s.accel->intersect(Ray({0, 0, 2}, {0, 0, 1}), si));
    EXPECT_EQ(si.shape, s.sphere.get());
    EXPECT_NEAR(si.t, 1.f, 1e-5f);

    EXPECT_FALSE(s.accel->intersect(Ray({0, 0, 10}, {0, 0, 1}), si));
    EXPECT_FALSE(s.accel->intersect(Ray({20, 0, 10}, {0, 0, -1}), si));
}

TEST(Accel, TmaxAndOcclusion) {
    Scene3 s;
    SurfaceInteraction si;
    EXPECT_FALSE(s.accel->intersect(Ray({5, 5, 10}, {0, 0, -1}, 9.9f), si));
    EXPECT_TRUE(s.accel->intersect(Ray({5, 5, 10}, {0, 0, -1}, 10.1f), si));
    EXPECT_TRUE(s.accel->occluded(Ray({0, 0, 10}, {0, 0, -1})));
    EXPECT_FALSE(s.accel->occluded(Ray({0, 0, 10}, {0, 0, -1}, 6.9f)));  // stops above the sphere
    EXPECT_TRUE(s.accel->occluded(Ray({0, 0, 10}, {0, 0, -1}, 7.1f)));
    EXPECT_FALSE(s.accel->occluded(Ray({5, 5, 10}, {0, 0, 1})));
    EXPECT_TRUE(s.accel->occluded(Ray({3, 0, 10}, {0, 0, -1})));  // disk, user geometry
    // Shadow ray between two floor points above the surface passes under nothing.
    EXPECT_FALSE(s.accel->occluded(Ray({5, 5, 0.01f}, {0, 1, 0}, 3.f)));
}

TEST(Accel, EmptyScene) {
    Accel accel({});
    SurfaceInteraction si;
    EXPECT_FALSE(accel.intersect(Ray({0, 0, 0}, {0, 0, 1}), si));
    EXPECT_FALSE(accel.occluded(Ray({0, 0, 0}, {0, 0, 1})));
}

TEST(Accel, CubeFromAllSides) {
    auto cube = make_shape(
        ShapeProps("cube").t("to_world", Transform::translate({0, 0, 0}) * Transform::scale(Vec3f(2.f))));
    Accel accel({cube.get()});
    const Vec3f dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const Vec3f& d : dirs) {
        SurfaceInteraction si;
        ASSERT_TRUE(
            accel.intersect(Ray(d * -10.f + Vec3f(0.1f, 0.2f, 0.3f) * (1.f - absdot(d, {1, 1, 1})), d), si));
        EXPECT_NEAR(si.t, 8.f, 1e-4f);
        EXPECT_NEAR(dot(si.n, -d), 1.f, 1e-5f);  // outward geometric normal
        EXPECT_NEAR(dot(si.sh_frame.n, -d), 1.f, 1e-5f);
        EXPECT_GE(si.uv.x, 0.f);
        EXPECT_LE(si.uv.x, 1.f);
        EXPECT_GE(si.uv.y, 0.f);
        EXPECT_LE(si.uv.y, 1.f);
    }
    EXPECT_NEAR(cube->surface_area(), 6.f * 16.f, 1e-3f);
}

TEST(Accel, ThreadsAgree) {
    Scene3 s;
    auto trace = [&](int i, SurfaceInteraction& si) {
        float a = 0.001f * float(i);
        return s.accel->intersect(Ray({std::sin(a) * 4.f, std::cos(a) * 4.f, 10.f},
                                      normalize(Vec3f(-std::sin(a), -std::cos(a), -2.5f))),
                                  si);
    };
    constexpr int N = 4000;
    std::vector<float> expected(N);
    for (int i = 0; i < N; ++i) {
        SurfaceInteraction si;
        expected[i] = trace(i, si) ? si.t : -1.f;
    }
    std::atomic<int> mismatches{0};
    std::vector<std::thread> threads;
    for (int k = 0; k < 4; ++k)
        threads.emplace_back([&, k] {
            for (int i = k; i < N; i += 4) {
                SurfaceInteraction si;
                float t = trace(i, si) ? si.t : -1.f;
                if (t != expected[i]) ++mismatches;
            }
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(mismatches.load(), 0);
}

namespace {

// Double-precision Möller-Trumbore, for the brute-force reference.
bool ray_triangle(const Ray& r, const Point3f& a, const Point3f& b, const Point3f& c, double& t) {
    Vec3d o(r.o), d(r.d), p0(a), e1 = Vec3d(b) - p0, e2 = Vec3d(c) - p0;
    Vec3d pv = cross(d, e2);
    double det = dot(e1, pv);
    if (std::abs(det) < 1e-300) return false;
    Vec3d tv = o - p0;
    double u = dot(tv, pv) / det;
    if (u < 0 || u > 1) return false;
    Vec3d qv = cross(tv, e1);
    double v = dot(d, qv) / det;
    if (v < 0 || u + v > 1) return false;
    t = dot(e2, qv) / det;
    return t > 0 && t < r.tmax;
}

// A triangle shape whose buffers have no spare capacity, to exercise the accel's padded copy.
struct TightMeshShape : Shape {
    TriangleMesh mesh;
    BBox3f bbox() const override {
        BBox3f b;
        for (auto& p : mesh.positions) b.expand(p);
        return b;
    }
    float surface_area() const override { return 0.f; }
    const TriangleMesh* triangle_mesh() const override { return &mesh; }
    SurfaceInteraction compute_surface_interaction(const Ray& ray, float t, uint32_t prim,
                                                   Vec2f) const override {
        SurfaceInteraction si;
        si.t = t;
        si.p = ray(t);
        si.prim_index = prim;
        si.shape = this;
        return si;
    }
    PositionSample sample_position(Point2f) const override { return {}; }
};

TriangleMesh bumpy_grid(int n) {
    TriangleMesh m;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            float x = 2.f * i / n - 1.f, y = 2.f * j / n - 1.f;
            m.positions.emplace_back(x, y, 0.2f * std::sin(5.f * x) * std::cos(4.f * y));
        }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            uint32_t a = uint32_t(i * (n + 1) + j), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    return m;
}

}  // namespace

TEST(Accel, MatchesBruteForce) {
    TightMeshShape tight;
    tight.mesh = bumpy_grid(40);
    tight.mesh.positions.shrink_to_fit();
    tight.mesh.indices.shrink_to_fit();
    auto sphere = make_shape(ShapeProps("sphere").p("center", {0.3f, 0.2f, 0.1f}).f("radius", 0.25));
    Accel accel({&tight, sphere.get()});
    int checked = 0, hits = 0;
    for (int i = 0; i < 3000; ++i) {
        float a = 0.37f * i, b = 0.11f * i;
        Point3f o(1.5f * std::cos(a), 1.5f * std::sin(a), 1.0f + 0.5f * std::sin(b));
        Point3f target(0.9f * std::sin(1.3f * i), 0.9f * std::cos(0.7f * i), 0.f);
        Ray ray(o, normalize(target - o), (i % 3 == 0) ? 1.5f : Infinity);
        double best = Infinity;
        uint32_t best_prim = 0;
        const Shape* best_shape = nullptr;
        for (size_t f = 0; f < tight.mesh.triangle_count(); ++f) {
            double t;
            const uint32_t* idx = &tight.mesh.indices[3 * f];
            if (ray_triangle(ray, tight.mesh.positions[idx[0]], tight.mesh.positions[idx[1]],
                             tight.mesh.positions[idx[2]], t) &&
                t < best) {
                best = t;
                best_prim = uint32_t(f);
                best_shape = &tight;
            }
        }
        float ts;
        Vec2f uv;
        if (sphere->intersect(ray, ts, uv) && ts < best) {
            best = ts;
            best_shape = sphere.get();
        }
        SurfaceInteraction si;
        bool hit = accel.intersect(ray, si);
        ASSERT_EQ(hit, best_shape != nullptr) << "ray " << i;
        EXPECT_EQ(accel.occluded(ray), hit) << "ray " << i;
        if (!hit) continue;
        ++hits;
        EXPECT_EQ(si.shape, best_shape) << "ray " << i;
        EXPECT_NEAR(si.t, best, 1e-4 * (1.0 + best)) << "ray " << i;
        if (best_shape == &tight) {
            EXPECT_EQ(si.prim_index, best_prim) << "ray " << i;
        }
        ++checked;
    }
    EXPECT_GT(hits, 1000);
    EXPECT_EQ(checked, hits);
}
