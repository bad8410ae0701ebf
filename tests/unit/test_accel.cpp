// Accel (Embree): closest hits across triangle meshes and analytic shapes, tmax, occlusion,
// the empty scene, and agreement between threads.
#include <gtest/gtest.h>

#include <atomic>
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
        disk = make_shape(ShapeProps("disk").t("to_world", Transform::translate({3, 0, 5})).b("flip_normals", true));
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
    auto cube = make_shape(ShapeProps("cube").t("to_world", Transform::translate({0, 0, 0}) * Transform::scale(Vec3f(2.f))));
    Accel accel({cube.get()});
    const Vec3f dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const Vec3f& d : dirs) {
        SurfaceInteraction si;
        ASSERT_TRUE(accel.intersect(Ray(d * -10.f + Vec3f(0.1f, 0.2f, 0.3f) * (1.f - absdot(d, {1, 1, 1})), d), si));
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
        return s.accel->intersect(Ray({std::sin(a) * 4.f, std::cos(a) * 4.f, 10.f}, normalize(Vec3f(-std::sin(a), -std::cos(a), -2.5f))), si);
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
