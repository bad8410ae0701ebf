// Point, spot and directional lights: Mitsuba's parameters, defaults, radiometry and errors.
#include <gtest/gtest.h>

#include <cmath>

#include "support/emitter_test_util.h"
#include "volguide/core/transform.h"
#include "volguide/render/emitters/spot_falloff.h"

using namespace volguide;
using volguide::test::EmitterBuilder;
using volguide::test::reference_point;

namespace {

void expect_color_near(const Color3& a, const Color3& b, float rel = 1e-5f) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a[c], b[c], rel * std::max(1.f, std::abs(b[c]))) << "channel " << c;
}

}  // namespace

TEST(PointEmitter, InverseSquareLaw) {
    auto e = EmitterBuilder("point")
                 .set("position", Vec3f(1.f, 2.f, 3.f))
                 .set("intensity", Color3(2.f, 4.f, 8.f), "rgb")
                 .build();
    EXPECT_EQ(e->flags(), uint32_t(emitter_flags::DeltaPosition));
    EXPECT_TRUE(e->is_delta());
    EXPECT_FALSE(e->is_infinite());
    for (float r : {0.5f, 1.f, 3.f}) {
        const Point3f ref = Point3f(1.f, 2.f, 3.f) + normalize(Vec3f(1.f, -2.f, 0.5f)) * r;
        auto [ds, w] = e->sample_direction(reference_point(ref), {0.3f, 0.7f});
        EXPECT_TRUE(ds.delta);
        EXPECT_EQ(ds.pdf, 1.f);
        EXPECT_NEAR(ds.dist, r, 1e-5f);
        EXPECT_NEAR(norm(ds.d), 1.f, 1e-6f);
        EXPECT_NEAR(norm(ref + ds.d * ds.dist - ds.p), 0.f, 1e-5f);
        expect_color_near(w, Color3(2.f, 4.f, 8.f) / (r * r));
        EXPECT_EQ(ds.emitter, e.get());
        EXPECT_EQ(e->pdf_direction(reference_point(ref), ds), 0.f);
    }
}

TEST(PointEmitter, DefaultsAndToWorld) {
    auto e =
        EmitterBuilder("point").set("to_world", Transform::translate({0.f, 0.f, 2.f}), "transform").build();
    auto [ds, w] = e->sample_direction(reference_point({0.f, 0.f, 0.f}), {0.f, 0.f});
    EXPECT_NEAR(ds.d.z, 1.f, 1e-6f);
    expect_color_near(w, Color3(0.25f));  // default intensity 1
}

TEST(PointEmitter, RejectsBadParameters) {
    EXPECT_THROW(
        EmitterBuilder("point").set("position", Vec3f(0.f)).set("to_world", Transform(), "transform").build(),
        InputError);
    EXPECT_THROW(EmitterBuilder("point").set("intensity", Color3(-1.f), "rgb").build(), InputError);
    EXPECT_THROW(EmitterBuilder("point").set("intensity", Color3(NAN), "rgb").build(), InputError);
    EXPECT_THROW(EmitterBuilder("point").set("radiance", Color3(1.f), "rgb").build(), InputError);  // unused
}

TEST(SpotFalloff, MitsubaProfile) {
    const SpotFalloff f(20.f, 15.f);
    auto dir = [](float deg) {
        const float t = deg_to_rad(deg);
        return Vec3f(std::sin(t), 0.f, std::cos(t));
    };
    EXPECT_EQ(f(dir(0.f)), 1.f);
    EXPECT_EQ(f(dir(14.9f)), 1.f);
    EXPECT_NEAR(f(dir(17.5f)), 0.5f, 1e-4f);  // linear in the angle between beam and cutoff
    EXPECT_NEAR(f(dir(16.f)), 0.8f, 1e-4f);
    EXPECT_NEAR(f(dir(19.f)), 0.2f, 1e-4f);
    EXPECT_EQ(f(dir(20.5f)), 0.f);
    EXPECT_EQ(f(dir(90.f)), 0.f);
    EXPECT_EQ(f(dir(180.f)), 0.f);
    EXPECT_EQ(f(dir(5.f) * 7.f), 1.f);  // length does not matter
}

TEST(SpotEmitter, DefaultsAndOrientation) {
    // Light at (0,0,-2) looking at the origin (+z); reference points at distance 2 off axis.
    const Transform to_world = Transform::look_at({0.f, 0.f, -2.f}, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f});
    auto e = EmitterBuilder("spot")
                 .set("to_world", to_world, "transform")
                 .set("intensity", Color3(4.f), "rgb")
                 .build();
    EXPECT_EQ(e->flags(), uint32_t(emitter_flags::DeltaPosition));
    auto at_angle = [&](float deg) {
        const float t = deg_to_rad(deg);
        const Point3f ref = Point3f(0.f, 0.f, -2.f) + Vec3f(std::sin(t), 0.f, std::cos(t)) * 2.f;
        return e->sample_direction(reference_point(ref), {0.5f, 0.5f});
    };
    // Default cutoff 20 degrees, beam width 15 degrees.
    auto [ds0, w0] = at_angle(0.f);
    EXPECT_TRUE(ds0.delta);
    EXPECT_NEAR(ds0.d.z, -1.f, 1e-6f);
    expect_color_near(w0, Color3(1.f));  // 4 / 2^2
    expect_color_near(at_angle(14.f).second, Color3(1.f));
    expect_color_near(at_angle(17.5f).second, Color3(0.5f), 1e-3f);
    EXPECT_EQ(at_angle(21.f).second, Color3(0.f));
    // Behind the light.
    EXPECT_EQ(e->sample_direction(reference_point({0.f, 0.f, -4.f}), {0.5f, 0.5f}).second, Color3(0.f));
}

TEST(SpotEmitter, ExplicitAngles) {
    auto e = EmitterBuilder("spot").set("cutoff_angle", 60.0).set("beam_width", 30.0).build();
    auto weight_at = [&](float deg) {
        const float t = deg_to_rad(deg);
        return e->sample_direction(reference_point(Vec3f(std::sin(t), 0.f, std::cos(t))), {0.f, 0.f}).second;
    };
    expect_color_near(weight_at(29.f), Color3(1.f));
    expect_color_near(weight_at(45.f), Color3(0.5f), 1e-3f);
    EXPECT_EQ(weight_at(61.f), Color3(0.f));
    // Only the cutoff given: the beam is 3/4 of it (45 degrees).
    auto e60 = EmitterBuilder("spot").set("cutoff_angle", 60.0).build();
    const float t = deg_to_rad(52.5f);
    auto w = e60->sample_direction(reference_point(Vec3f(std::sin(t), 0.f, std::cos(t))), {0.f, 0.f}).second;
    expect_color_near(w, Color3(0.5f), 1e-3f);
}

TEST(SpotEmitter, RejectsBadParameters) {
    EXPECT_THROW(EmitterBuilder("spot").set("cutoff_angle", 10.0).set("beam_width", 20.0).build(),
                 InputError);
    EXPECT_THROW(EmitterBuilder("spot").set("cutoff_angle", -5.0).build(), InputError);
    EXPECT_THROW(EmitterBuilder("spot").set("intensity", Color3(-1.f), "rgb").build(), InputError);
    try {
        EmitterBuilder("spot").set("texture", Color3(1.f), "rgb").build();
        FAIL() << "expected an error for 'texture'";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("texture"), std::string::npos) << e.what();
    }
}

TEST(DirectionalEmitter, IrradianceAndDirection) {
    auto e = EmitterBuilder("directional")
                 .set("direction", Vec3f(0.f, -2.f, 0.f))
                 .set("irradiance", Color3(3.f, 2.f, 1.f), "rgb")
                 .build();
    EXPECT_EQ(e->flags(), uint32_t(emitter_flags::Infinite | emitter_flags::DeltaDirection));
    e->set_scene_bounds(BBox3f({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
    const Point3f ref(0.2f, -0.3f, 0.1f);
    auto [ds, w] = e->sample_direction(reference_point(ref), {0.1f, 0.9f});
    EXPECT_TRUE(ds.delta);
    EXPECT_EQ(ds.pdf, 1.f);
    EXPECT_NEAR(ds.d.y, 1.f, 1e-6f);  // towards the light: against the propagation direction
    EXPECT_TRUE(std::isinf(ds.dist));
    // The sample point lies outside the scene's bounding sphere, along ds.d.
    EXPECT_GT(norm(ds.p), std::sqrt(3.f));
    EXPECT_NEAR(norm(normalize(ds.p - ref) - ds.d), 0.f, 1e-5f);
    // Irradiance on a surface facing the light is delivered undivided (pdf 1).
    expect_color_near(w, Color3(3.f, 2.f, 1.f));
    EXPECT_EQ(e->pdf_direction(reference_point(ref), ds), 0.f);
    EXPECT_EQ(e->eval(volguide::test::escaped_ray(ds.d)), Color3(0.f));
}

TEST(DirectionalEmitter, ToWorldAndDefaults) {
    // Default: propagates along +z of to_world; rotate +z onto +x.
    auto e = EmitterBuilder("directional")
                 .set("to_world", Transform::rotate({0.f, 1.f, 0.f}, 90.f), "transform")
                 .build();
    auto [ds, w] = e->sample_direction(reference_point(Point3f(0.f)), {0.f, 0.f});
    EXPECT_NEAR(ds.d.x, -1.f, 1e-6f);
    expect_color_near(w, Color3(1.f));
    EXPECT_THROW(EmitterBuilder("directional")
                     .set("direction", Vec3f(1.f, 0.f, 0.f))
                     .set("to_world", Transform(), "transform")
                     .build(),
                 InputError);
    EXPECT_THROW(EmitterBuilder("directional").set("direction", Vec3f(0.f)).build(), InputError);
}

TEST(EmitterFactory, UnknownTypeIsAnError) {
    EXPECT_THROW(EmitterBuilder("sunsky").build(), InputError);
}
