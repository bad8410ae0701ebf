// Environment map: Mitsuba's orientation and bilinear lookup, sample/pdf/eval consistency, errors.
#include <gtest/gtest.h>

#include <cmath>

#include "support/emitter_test_util.h"
#include "volguide/core/sampler.h"
#include "volguide/core/transform.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// Pixel (x, y) holds 1 + x + 10 y in red, a constant in green, y in blue.
Image labelled_image(int w, int h) {
    Image image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) image.at(x, y) = Color3(1.f + x + 10.f * y, 0.5f, float(y));
    return image;
}

std::shared_ptr<Emitter> envmap(const std::string& file, float scale = 1.f, const Transform& to_world = {}) {
    EmitterBuilder b("envmap");
    b.set("filename", file);
    if (scale != 1.f) b.set("scale", double(scale));
    if (!to_world.is_identity()) b.set("to_world", to_world, "transform");
    return b.build();
}

void expect_envmap_color_near(const Color3& a, const Color3& b, float rel) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a[c], b[c], rel * std::max(1.f, std::abs(b[c]))) << "channel " << c;
}

}  // namespace

TEST(EnvmapEmitter, PixelCentresAndAxes) {
    const int w = 8, h = 5;
    const Image image = labelled_image(w, h);
    auto e = envmap(write_temp_exr("labelled.exr", image));
    EXPECT_EQ(e->flags(), uint32_t(emitter_flags::Infinite));
    // Column x is centred on u = (x + 1/2) / w, row y lies on v = y / (h - 1).
    for (int y = 1; y < h - 1; ++y)
        for (int x = 0; x < w; ++x) {
            const Vec3f d = envmap_direction((x + 0.5f) / w, y / float(h - 1));
            expect_envmap_color_near(e->eval(escaped_ray(d)), image.at(x, y), 1e-4f);
        }
}

TEST(EnvmapEmitter, HandCheckedOrientation) {
    // 4x3 map: the middle row is the horizon. u = atan2(x, -z) / 2pi, so looking along -z is u = 0,
    // +x is u = 1/4, +z is u = 1/2, -x is u = 3/4; pixel centres sit half a texel to the right.
    const Image image = labelled_image(4, 3);
    auto e = envmap(write_temp_exr("small.exr", image));
    auto red = [&](const Vec3f& d) { return e->eval(escaped_ray(d)).r; };
    const float row = 10.f;                                 // row 1 adds 10
    EXPECT_NEAR(red({1.f, 0.f, 0.f}), row + 1.5f, 1e-4f);   // between pixels 0 and 1
    EXPECT_NEAR(red({0.f, 0.f, 1.f}), row + 2.5f, 1e-4f);   // between pixels 1 and 2
    EXPECT_NEAR(red({-1.f, 0.f, 0.f}), row + 3.5f, 1e-4f);  // between pixels 2 and 3
    EXPECT_NEAR(red({0.f, 0.f, -1.f}), row + 2.5f, 1e-4f);  // between pixel 3 and pixel 0 (wraps)
    // +y is the top row (v = 0): all of row 0's columns meet there; blue channel carries the row.
    EXPECT_NEAR(e->eval(escaped_ray({0.f, 1.f, 0.f})).b, 0.f, 1e-6f);
    EXPECT_NEAR(e->eval(escaped_ray(normalize(Vec3f(0.f, -1.f, 1e-3f)))).b, 2.f, 1e-3f);
}

TEST(EnvmapEmitter, ScaleAndToWorld) {
    const Image image = labelled_image(8, 6);
    const std::string file = write_temp_exr("labelled86.exr", image);
    auto plain = envmap(file);
    auto scaled = envmap(file, 2.5f);
    const Transform rot = Transform::rotate({0.3f, 1.f, -0.2f}, 37.f);
    auto rotated = envmap(file, 1.f, rot);
    Sampler s(7, 0, 0);
    for (int i = 0; i < 100; ++i) {
        const Vec3f d = normalize(envmap_direction(s.next_1d(), s.next_1d()));
        const Color3 base = plain->eval(escaped_ray(d));
        expect_envmap_color_near(scaled->eval(escaped_ray(d)), base * 2.5f, 1e-5f);
        expect_envmap_color_near(rotated->eval(escaped_ray(normalize(rot.apply_vector(d)))), base, 2e-3f);
    }
}

TEST(EnvmapEmitter, SamplePdfEvalAgree) {
    Image image = labelled_image(16, 9);
    image.at(3, 4) = Color3(500.f, 20.f, 1.f);                  // a hot spot
    for (int x = 0; x < 16; ++x) image.at(x, 6) = Color3(0.f);  // a black band
    for (bool rotate : {false, true}) {
        auto e = envmap(write_temp_exr("hot.exr", image), 1.f,
                        rotate ? Transform::rotate({1.f, 0.f, 0.f}, 90.f) : Transform());
        e->set_scene_bounds(BBox3f({-1.f, -2.f, -1.f}, {1.f, 2.f, 3.f}));
        const Interaction ref = reference_point({0.5f, 0.f, 0.2f});
        Sampler s(3, 0, 0);
        for (int i = 0; i < 2000; ++i) {
            auto [ds, w] = e->sample_direction(ref, s.next_2d());
            ASSERT_GT(ds.pdf, 0.f);
            EXPECT_FALSE(ds.delta);
            EXPECT_EQ(ds.emitter, e.get());
            EXPECT_NEAR(norm(ds.d), 1.f, 1e-5f);
            EXPECT_TRUE(std::isinf(ds.dist));
            EXPECT_GT(norm(ds.p - Point3f(0.f, 0.f, 1.f)), norm(Vec3f(1.f, 2.f, 2.f)));  // outside the scene
            const float pdf = e->pdf_direction(ref, ds);
            EXPECT_NEAR(pdf, ds.pdf, 2e-3f * ds.pdf) << i;
            const Color3 radiance = e->eval(escaped_ray(ds.d));
            expect_envmap_color_near(w * ds.pdf, radiance, 2e-3f);
        }
    }
}

TEST(EnvmapEmitter, MisCompensation) {
    // Luminance below the average gets no samples; sampling and pdf stay consistent.
    Image image(8, 5, Color3(0.1f));
    image.at(2, 2) = Color3(10.f);
    const std::string file = write_temp_exr("mis.exr", image);
    auto e = EmitterBuilder("envmap").set("filename", file).set("mis_compensation", true).build();
    const Interaction ref = reference_point(Point3f(0.f));
    Sampler s(11, 0, 0);
    for (int i = 0; i < 500; ++i) {
        auto [ds, w] = e->sample_direction(ref, s.next_2d());
        ASSERT_GT(ds.pdf, 0.f);
        EXPECT_NEAR(e->pdf_direction(ref, ds), ds.pdf, 2e-3f * ds.pdf);
        // Every sample lies within one texel of the bright pixel's vertex.
        EXPECT_NEAR(ds.uv.y, 0.5f, 0.25f + 1e-4f);
    }
    DirectionSample away;
    away.d = envmap_direction(6.5f / 8.f, 0.5f);
    EXPECT_EQ(e->pdf_direction(ref, away), 0.f);
    // Without compensation the dim part is sampled too.
    auto plain = EmitterBuilder("envmap").set("filename", file).build();
    EXPECT_GT(plain->pdf_direction(ref, away), 0.f);
}

TEST(EnvmapEmitter, BlackMapEmitsNothing) {
    auto e = envmap(write_temp_exr("black.exr", Image(4, 3)));
    auto [ds, w] = e->sample_direction(reference_point(Point3f(0.f)), {0.3f, 0.4f});
    EXPECT_EQ(w, Color3(0.f));
    EXPECT_EQ(ds.pdf, 0.f);
    EXPECT_EQ(e->pdf_direction(reference_point(Point3f(0.f)), ds), 0.f);
}

TEST(EnvmapEmitter, Errors) {
    try {
        envmap("/nonexistent/sky.exr");
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("sky.exr"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("test.xml"), std::string::npos) << e.what();
    }
    EXPECT_THROW(envmap(write_temp_exr("tiny.exr", Image(2, 2, Color3(1.f)))), InputError);
    EXPECT_THROW(envmap(write_temp_exr("ok.exr", Image(4, 3, Color3(1.f))), -1.f), InputError);
    EXPECT_THROW(EmitterBuilder("envmap").build(), InputError);  // filename is required
}

TEST(ConstantEmitter, UniformSphere) {
    auto e = EmitterBuilder("constant").set("radiance", Color3(0.5f, 1.f, 2.f), "rgb").build();
    EXPECT_EQ(e->flags(), uint32_t(emitter_flags::Infinite));
    e->set_scene_bounds(BBox3f({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
    Sampler s(1, 0, 0);
    for (int i = 0; i < 100; ++i) {
        const Interaction ref = reference_point({0.f, 0.5f, 0.f});
        auto [ds, w] = e->sample_direction(ref, s.next_2d());
        EXPECT_NEAR(ds.pdf, InvFourPi, 1e-7f);
        EXPECT_NEAR(e->pdf_direction(ref, ds), InvFourPi, 1e-7f);
        expect_envmap_color_near(w * ds.pdf, Color3(0.5f, 1.f, 2.f), 1e-5f);
        EXPECT_EQ(e->eval(escaped_ray(ds.d)), Color3(0.5f, 1.f, 2.f));
        EXPECT_GT(norm(ds.p), std::sqrt(3.f));
    }
    EXPECT_EQ(EmitterBuilder("constant").build()->eval(escaped_ray({0.f, 0.f, 1.f})), Color3(1.f));
    EXPECT_THROW(EmitterBuilder("constant").set("radiance", Color3(-1.f), "rgb").build(), InputError);
}
