// Sphere and disk: exact hits (t, normal, uv, frame), to_world / center / radius composition,
// flip_normals, parameter validation, position sampling.
#include <gtest/gtest.h>

#include <cmath>

#include "test_shape_util.h"
#include "volguide/core/error.h"

using namespace volguide;
using namespace volguide::test;

namespace {

SurfaceInteraction hit(const Shape& s, const Ray& r) {
    float t;
    Vec2f uv;
    EXPECT_TRUE(s.intersect(r, t, uv));
    return s.compute_surface_interaction(r, t, 0, uv);
}

void expect_vec_near(const Vec3f& a, const Vec3f& b, float tol = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

void expect_orthonormal_frame(const SurfaceInteraction& si) {
    EXPECT_NEAR(norm(si.sh_frame.s), 1.f, 1e-5f);
    EXPECT_NEAR(norm(si.sh_frame.t), 1.f, 1e-5f);
    EXPECT_NEAR(dot(si.sh_frame.s, si.sh_frame.n), 0.f, 1e-5f);
    EXPECT_NEAR(dot(si.sh_frame.t, si.sh_frame.n), 0.f, 1e-5f);
    expect_vec_near(cross(si.sh_frame.n, si.sh_frame.s), si.sh_frame.t);
}

}  // namespace

TEST(ShapeSphere, HitFromOutside) {
    auto s = make_shape(ShapeProps("sphere").p("center", {1, 2, 3}).f("radius", 2));
    Ray r({1, 2, -10}, {0, 0, 1});
    SurfaceInteraction si = hit(*s, r);
    EXPECT_NEAR(si.t, 11.f, 1e-5f);
    expect_vec_near(si.p, {1, 2, 1});
    expect_vec_near(si.n, {0, 0, -1});
    expect_vec_near(si.sh_frame.n, {0, 0, -1});
    EXPECT_NEAR(si.uv.y, 1.f, 1e-5f);  // theta = pi at the -z pole
    EXPECT_NEAR(si.wi.z, 1.f, 1e-5f);  // -ray.d is along the normal
    EXPECT_EQ(si.shape, s.get());
    expect_orthonormal_frame(si);
    EXPECT_NEAR(s->surface_area(), 16.f * Pi, 1e-4f);
}

TEST(ShapeSphere, HitFromInsideAndUv) {
    auto s = make_shape(ShapeProps("sphere"));
    // From the center towards +y: hits (0,1,0), phi = pi/2, theta = pi/2.
    SurfaceInteraction si = hit(*s, Ray({0, 0, 0}, {0, 1, 0}));
    EXPECT_NEAR(si.t, 1.f, 1e-6f);
    expect_vec_near(si.n, {0, 1, 0});
    EXPECT_NEAR(si.uv.x, 0.25f, 1e-6f);
    EXPECT_NEAR(si.uv.y, 0.5f, 1e-6f);
    EXPECT_LT(si.wi.z, 0.f);  // arriving from inside
    // dp_du follows increasing phi: at (0,1,0) that is -x; the tangent s of the frame follows it.
    expect_vec_near(normalize(si.dp_du), {-1, 0, 0});
    expect_vec_near(si.sh_frame.s, {-1, 0, 0});
    // Direction towards -y: phi = 3pi/2 -> u = 0.75.
    EXPECT_NEAR(hit(*s, Ray({0, 0, 0}, {0, -1, 0})).uv.x, 0.75f, 1e-6f);
}

TEST(ShapeSphere, MissesAndRespectsTmax) {
    auto s = make_shape(ShapeProps("sphere"));
    float t;
    Vec2f uv;
    EXPECT_FALSE(s->intersect(Ray({0, 2, -5}, {0, 0, 1}), t, uv));
    EXPECT_FALSE(s->intersect(Ray({0, 0, -5}, {0, 0, 1}, 3.9f), t, uv));
    EXPECT_TRUE(s->intersect(Ray({0, 0, -5}, {0, 0, 1}, 4.1f), t, uv));
    EXPECT_FALSE(s->intersect(Ray({0, 0, 5}, {0, 0, 1}), t, uv));  // sphere behind the origin
}

TEST(ShapeSphere, PreciseFarAway) {
    // The projected-origin quadratic keeps full precision for distant origins.
    auto s = make_shape(ShapeProps("sphere").f("radius", 0.01));
    SurfaceInteraction si = hit(*s, Ray({0, 0, -1e4f}, {0, 0, 1}));
    EXPECT_NEAR(si.p.z, -0.01f, 1e-6f);
}

TEST(ShapeSphere, ToWorldComposition) {
    // to_world is applied after center/radius (Mitsuba: to_world * translate(center) * scale(radius)).
    auto s =
        make_shape(ShapeProps("sphere").p("center", {1, 0, 0}).t("to_world", Transform::scale(Vec3f(2.f))));
    BBox3f b = s->bbox();
    expect_vec_near(b.lo, {0, -2, -2});
    expect_vec_near(b.hi, {4, 2, 2});
}

TEST(ShapeSphere, FlipNormalsAndMirror) {
    auto flipped = make_shape(ShapeProps("sphere").b("flip_normals", true));
    expect_vec_near(hit(*flipped, Ray({0, 0, -5}, {0, 0, 1})).n, {0, 0, 1});
    // A mirroring to_world turns the sphere inside out, as in Mitsuba.
    auto mirrored = make_shape(ShapeProps("sphere").t("to_world", Transform::scale({-1, 1, 1})));
    expect_vec_near(hit(*mirrored, Ray({0, 0, -5}, {0, 0, 1})).n, {0, 0, 1});
}

TEST(ShapeSphere, RejectsBadRadius) {
    EXPECT_THROW(make_shape(ShapeProps("sphere").f("radius", -1)), InputError);
    EXPECT_THROW(make_shape(ShapeProps("sphere").f("radius", NAN)), InputError);
    EXPECT_THROW(make_shape(ShapeProps("sphere").f("radius", 0)), InputError);
}

TEST(ShapeSphere, UnknownParameterIsAnError) {
    EXPECT_THROW(make_shape(ShapeProps("sphere").f("radiu", 1)), InputError);
}

TEST(ShapeSphere, SamplePositionOnSurface) {
    auto s = make_shape(ShapeProps("sphere").p("center", {0, 0, 1}).f("radius", 0.5));
    for (int i = 0; i < 64; ++i) {
        PositionSample ps = s->sample_position({(i + 0.5f) / 64.f, std::fmod(i * 0.618f, 1.f)});
        EXPECT_NEAR(norm(ps.p - Vec3f(0, 0, 1)), 0.5f, 1e-5f);
        expect_vec_near(ps.n, normalize(ps.p - Vec3f(0, 0, 1)));
        EXPECT_NEAR(ps.pdf, 1.f / (Pi), 1e-5f);  // area = 4 pi r^2 = pi
    }
}

TEST(ShapeDisk, HitNormalUv) {
    auto d = make_shape(
        ShapeProps("disk").t("to_world", Transform::translate({0, 0, 2}) * Transform::scale({2, 2, 1})));
    SurfaceInteraction si = hit(*d, Ray({1, 0, 5}, {0, 0, -1}));
    EXPECT_NEAR(si.t, 3.f, 1e-6f);
    expect_vec_near(si.p, {1, 0, 2});
    expect_vec_near(si.n, {0, 0, 1});
    EXPECT_NEAR(si.uv.x, 0.5f, 1e-6f);  // r in object space
    EXPECT_NEAR(si.uv.y, 0.f, 1e-6f);   // phi = 0
    EXPECT_NEAR(si.wi.z, 1.f, 1e-6f);
    expect_orthonormal_frame(si);
    EXPECT_NEAR(hit(*d, Ray({0, -1, 5}, {0, 0, -1})).uv.y, 0.75f, 1e-6f);
    EXPECT_NEAR(d->surface_area(), 4.f * Pi, 1e-5f);
    float t;
    Vec2f uv;
    EXPECT_FALSE(d->intersect(Ray({2.1f, 0, 5}, {0, 0, -1}), t, uv));
    EXPECT_FALSE(d->intersect(Ray({1, 0, 5}, {1, 0, 0}), t, uv));  // parallel
}

TEST(ShapeDisk, FlipNormalsAndSampling) {
    auto d = make_shape(ShapeProps("disk").b("flip_normals", true));
    expect_vec_near(hit(*d, Ray({0.2f, 0.3f, 1}, {0, 0, -1})).n, {0, 0, -1});
    for (int i = 0; i < 32; ++i) {
        PositionSample ps = d->sample_position({(i + 0.5f) / 32.f, std::fmod(i * 0.618f, 1.f)});
        EXPECT_LE(ps.p.x * ps.p.x + ps.p.y * ps.p.y, 1.f + 1e-6f);
        EXPECT_EQ(ps.p.z, 0.f);
        expect_vec_near(ps.n, {0, 0, -1});
        EXPECT_NEAR(ps.pdf, InvPi, 1e-6f);
    }
}
