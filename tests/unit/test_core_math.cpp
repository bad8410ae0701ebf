#include <gtest/gtest.h>

#include "volguide/core/distribution.h"
#include "volguide/core/frame.h"
#include "volguide/core/properties.h"
#include "volguide/core/sampler.h"
#include "volguide/core/transform.h"

using namespace volguide;

TEST(Transform, InverseRoundTrip) {
    Transform t = Transform::translate({1, 2, 3}) * Transform::rotate({0.3f, 1, 0.2f}, 37.f) *
                  Transform::scale({2, 3, 0.5f});
    Point3f p(0.4f, -1.2f, 2.5f);
    Point3f q = t.inverse().apply_point(t.apply_point(p));
    EXPECT_NEAR(q.x, p.x, 1e-5);
    EXPECT_NEAR(q.y, p.y, 1e-5);
    EXPECT_NEAR(q.z, p.z, 1e-5);
}

TEST(Transform, RotateIsRightHanded) {
    Vec3f v = Transform::rotate({0, 0, 1}, 90.f).apply_vector({1, 0, 0});
    EXPECT_NEAR(v.x, 0.f, 1e-6);
    EXPECT_NEAR(v.y, 1.f, 1e-6);
}

TEST(Transform, LookAtMapsForwardToTarget) {
    Transform t = Transform::look_at({0, 0.5f, 4}, {0, -0.5f, 0}, {0, 1, 0});
    Vec3f fwd = normalize(t.apply_vector({0, 0, 1}));
    Vec3f expected = normalize(Vec3f(0, -1, -4));
    EXPECT_NEAR(dot(fwd, expected), 1.f, 1e-6);
    // Mitsuba: camera +x is "left" = cross(up, dir).
    Vec3f left = t.apply_vector({1, 0, 0});
    EXPECT_LT(left.x, -0.9f);  // looking down -z with up +y, the viewer's left is -x
}

TEST(Frame, Orthonormal) {
    Frame f(normalize(Vec3f(0.2f, -0.7f, -0.4f)));
    EXPECT_NEAR(dot(f.s, f.t), 0.f, 1e-6);
    EXPECT_NEAR(dot(f.s, f.n), 0.f, 1e-6);
    EXPECT_NEAR(norm(f.s), 1.f, 1e-6);
    Vec3f v(0.3f, 0.1f, -0.2f);
    Vec3f w = f.to_world(f.to_local(v));
    EXPECT_NEAR(w.x, v.x, 1e-6);
}

TEST(Sampler, PureFunctionOfCoordinates) {
    Sampler a(7, 123, 4), b(7, 123, 4), c(7, 124, 4);
    for (int i = 0; i < 10; ++i) {
        float x = a.next_1d();
        EXPECT_EQ(x, b.next_1d());
        EXPECT_NE(x, c.next_1d());
        EXPECT_GE(x, 0.f);
        EXPECT_LT(x, 1.f);
    }
}

TEST(Sampler, UniformMean) {
    Sampler s(1, 2, 3);
    double sum = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) sum += s.next_1d();
    // Mean of U(0,1): sd of the mean = sqrt(1/12/n); 5 sigma.
    EXPECT_NEAR(sum / n, 0.5, 5 * std::sqrt(1.0 / 12 / n));
}

TEST(DiscreteDistribution, SampleReuse) {
    float w[] = {1.f, 0.f, 3.f};
    DiscreteDistribution d(w);
    EXPECT_FLOAT_EQ(d.pmf(0), 0.25f);
    float u = 0.5f;
    EXPECT_EQ(d.sample_reuse(u), 2u);
    EXPECT_NEAR(u, (0.5f - 0.25f) / 0.75f, 1e-6);
    u = 0.1f;
    EXPECT_EQ(d.sample_reuse(u), 0u);
    EXPECT_NEAR(u, 0.4f, 1e-6);
}

TEST(Properties, UnusedParameterIsAnError) {
    Properties p("bsdf", "diffuse", {"scene.xml", 3});
    p.set("reflectance", "rgb", Color3(0.5f), {"scene.xml", 4});
    p.set("reflectanse", "rgb", Color3(0.5f), {"scene.xml", 5});
    EXPECT_EQ(p.get_color("reflectance"), Color3(0.5f));
    try {
        p.check_all_used();
        FAIL() << "expected an error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.location().line, 5);
        EXPECT_NE(std::string(e.what()).find("reflectanse"), std::string::npos);
    }
}
