// `shapegroup` / `instance` (issue 40): hits through an Embree instance of a group equal the hits on
// the same shapes transformed directly (analytic sphere and mesh, rotated, scaled, moved), a group
// placed twice, occlusion, and the loader's errors.
#include <gtest/gtest.h>

#include <cmath>

#include "test_shape_util.h"
#include "volguide/geometry/accel.h"
#include "volguide/geometry/instance.h"

using namespace volguide;
using namespace volguide::test;

namespace {

const Transform kInstanceSphereLocal = Transform::translate({1, 0, 0});
const Transform kInstanceRectLocal = Transform::rotate({0, 1, 0}, -80.f) * Transform::scale({1.2f, 1.2f, 1.2f});

std::shared_ptr<Shape> instance_sphere(const Transform& to_world) {
    return make_shape(ShapeProps("sphere").f("radius", 0.5).t("to_world", to_world * kInstanceSphereLocal));
}
std::shared_ptr<Shape> instance_rect(const Transform& to_world) {
    return make_shape(ShapeProps("rectangle").t("to_world", to_world * kInstanceRectLocal));
}

std::shared_ptr<Shape> instance_of(const std::shared_ptr<Shape>& a, const std::shared_ptr<Shape>& b,
                                   const Transform& to_world, std::shared_ptr<ShapeGroup>* group_out = nullptr) {
    ShapeProps gp("shapegroup");
    gp.set("", "shape", ObjectPtr(a));
    gp.set("", "shape", ObjectPtr(b));
    auto group = std::dynamic_pointer_cast<ShapeGroup>(create_shape(gp.props));
    gp.props.check_all_used();
    if (group_out) *group_out = group;
    ShapeProps ip("instance");
    ip.set("", "shape", ObjectPtr(group));
    ip.t("to_world", to_world);
    return make_shape(ip);
}

void instance_expect_error(ShapeProps sp, const std::string& fragment) {
    try {
        make_shape(sp);
        ADD_FAILURE() << "expected an input error mentioning '" << fragment << "'";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(Instance, HitsEqualTheDirectlyTransformedShapes) {
    const Transform to_world = Transform::translate({0.3f, -0.2f, 2.f}) * Transform::rotate({1, 1, 0}, 35.f) *
                               Transform::scale({1.3f, 1.3f, 1.3f});  // the direct sphere needs a similarity
    auto sphere = instance_sphere(Transform()), rect = instance_rect(Transform());
    std::shared_ptr<ShapeGroup> group;
    auto instance = instance_of(sphere, rect, to_world, &group);
    auto ref_sphere = instance_sphere(to_world), ref_rect = instance_rect(to_world);
    Accel inst_accel({instance.get()});
    Accel ref_accel({ref_sphere.get(), ref_rect.get()});

    int hits = 0;
    for (int i = 0; i < 21; ++i)
        for (int j = 0; j < 21; ++j) {
            const Point3f target(-2.f + 0.2f * float(i), -2.f + 0.2f * float(j), 2.f);
            const Point3f origin(-6.f, -4.f, 1.f);
            const Ray ray(origin, normalize(target - origin));
            SurfaceInteraction a, b;
            const bool hit_a = inst_accel.intersect(ray, a), hit_b = ref_accel.intersect(ray, b);
            ASSERT_EQ(hit_a, hit_b) << i << " " << j;
            EXPECT_EQ(inst_accel.occluded(ray), hit_b);
            if (!hit_b) continue;
            ++hits;
            EXPECT_EQ(a.shape == sphere.get(), b.shape == ref_sphere.get());
            EXPECT_EQ(a.shape == rect.get(), b.shape == ref_rect.get());
            EXPECT_NEAR(a.t, b.t, 1e-4f);
            EXPECT_NEAR(norm(a.p - b.p), 0.f, 1e-4f);
            EXPECT_NEAR(dot(a.n, b.n), 1.f, 1e-5f);
            EXPECT_NEAR(dot(a.sh_frame.n, b.sh_frame.n), 1.f, 1e-5f);
            EXPECT_NEAR(dot(a.sh_frame.s, b.sh_frame.s), 1.f, 1e-4f);
            EXPECT_NEAR(norm(a.wi - b.wi), 0.f, 1e-4f);
            EXPECT_NEAR(a.uv.x, b.uv.x, 1e-4f);
            EXPECT_NEAR(a.uv.y, b.uv.y, 1e-4f);
        }
    EXPECT_GT(hits, 40);
    EXPECT_EQ(group->shapes().size(), 2u);
}

TEST(Instance, OneGroupPlacedTwice) {
    auto sphere = instance_sphere(Transform()), rect = instance_rect(Transform());
    std::shared_ptr<ShapeGroup> group;
    auto first = instance_of(sphere, rect, Transform(), &group);
    ShapeProps ip("instance");
    ip.set("", "shape", ObjectPtr(group));
    ip.t("to_world", Transform::translate({0, 0, 5}));
    auto second = make_shape(ip);
    Accel accel({first.get(), second.get()});
    SurfaceInteraction si;
    // Down through the sphere of the second placement (centre (1, 0, 5)), then the first's.
    ASSERT_TRUE(accel.intersect(Ray({1, 0, 10}, {0, 0, -1}), si));
    EXPECT_EQ(si.shape, sphere.get());
    EXPECT_NEAR(si.t, 4.5f, 1e-5f);
    ASSERT_TRUE(accel.intersect(Ray({1, 0, 4}, {0, 0, -1}), si));
    EXPECT_NEAR(si.t, 3.5f, 1e-5f);
    EXPECT_NEAR(si.p.z, 0.5f, 1e-5f);
    EXPECT_NEAR(second->bbox().lo.z - first->bbox().lo.z, 5.f, 1e-4f);
    EXPECT_NEAR(second->bbox().hi.z - first->bbox().hi.z, 5.f, 1e-4f);
}

TEST(Instance, Errors) {
    instance_expect_error(ShapeProps("instance"), "exactly one referenced shapegroup");
    ShapeProps not_group("instance");
    not_group.set("", "shape", ObjectPtr(instance_sphere(Transform())));
    instance_expect_error(not_group, "not a shapegroup");
    instance_expect_error(ShapeProps("shapegroup"), "the group has no shapes");
}
