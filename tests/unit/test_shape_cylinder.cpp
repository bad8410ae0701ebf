// Mitsuba 3's analytic cylinder (issue 40): placement from p0, p1, radius and to_world, hits from
// outside and inside (open tube, no caps), outward normal and flip_normals, uv = (phi / 2pi, height),
// area, and the parameter errors.
#include <gtest/gtest.h>

#include <cmath>

#include "test_shape_util.h"
#include "volguide/core/error.h"
#include "volguide/geometry/accel.h"

using namespace volguide;
using namespace volguide::test;

namespace {

bool trace_cylinder(const Shape& s, const Ray& r, SurfaceInteraction& si) {
    Accel accel({&s});
    return accel.intersect(r, si);
}

TEST(ShapeCylinder, HitsNormalsUvAndArea) {
    auto c = make_shape(ShapeProps("cylinder").p("p0", {0, 0, 1}).p("p1", {0, 0, 3}).f("radius", 0.5));
    EXPECT_NEAR(c->surface_area(), 2.0 * M_PI * 0.5 * 2.0, 1e-5);
    SurfaceInteraction si;
    ASSERT_TRUE(trace_cylinder(*c, Ray({5, 0, 2}, {-1, 0, 0}), si));  // from outside along -x
    EXPECT_NEAR(si.t, 4.5f, 1e-5f);
    EXPECT_NEAR(si.n.x, 1.f, 1e-5f);  // outward
    EXPECT_NEAR(si.uv.y, 0.5f, 1e-5f);  // half way up
    ASSERT_TRUE(trace_cylinder(*c, Ray({0, 0, 2}, {0, 1, 0}), si));  // from the axis: the inside
    EXPECT_NEAR(si.t, 0.5f, 1e-5f);
    EXPECT_NEAR(si.n.y, 1.f, 1e-5f);
    EXPECT_FALSE(trace_cylinder(*c, Ray({0, 0, 5}, {0, 0, -1}), si));  // along the axis: open ends
    EXPECT_FALSE(trace_cylinder(*c, Ray({5, 0, 3.5f}, {-1, 0, 0}), si));  // above p1
    auto flipped = make_shape(ShapeProps("cylinder").b("flip_normals", true));
    ASSERT_TRUE(trace_cylinder(*flipped, Ray({5, 0, 0.5f}, {-1, 0, 0}), si));
    EXPECT_NEAR(si.n.x, -1.f, 1e-5f);
    // u goes around the axis: a quarter turn apart, u differs by 1/4 (mod 1).
    SurfaceInteraction a, b;
    ASSERT_TRUE(trace_cylinder(*flipped, Ray({5, 0, 0.5f}, {-1, 0, 0}), a));
    ASSERT_TRUE(trace_cylinder(*flipped, Ray({0, 5, 0.5f}, {0, -1, 0}), b));
    const float du = std::fmod(b.uv.x - a.uv.x + 1.f, 1.f);
    EXPECT_TRUE(std::abs(du - 0.25f) < 1e-4f || std::abs(du - 0.75f) < 1e-4f) << du;
}

TEST(ShapeCylinder, Errors) {
    EXPECT_THROW(make_shape(ShapeProps("cylinder").f("radius", 0)), InputError);
    EXPECT_THROW(make_shape(ShapeProps("cylinder").p("p1", {0, 0, 0})), InputError);
    EXPECT_THROW(make_shape(ShapeProps("cylinder").t("to_world", Transform::scale({1, 2, 1}))), InputError);
}

}  // namespace
