// Built-in mesh shapes (rectangle, cube) and the parts every shape shares: Mitsuba's uv layout,
// orientation under mirroring transforms, flip_normals, BSDF/emitter children (init_common) and
// the default area-to-solid-angle conversion.
#include <gtest/gtest.h>

#include "test_shape_util.h"
#include "volguide/core/error.h"
#include "volguide/geometry/accel.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/emitter.h"

using namespace volguide;
using namespace volguide::test;

namespace {

SurfaceInteraction trace(const Shape& s, const Ray& r) {
    Accel accel({&s});
    SurfaceInteraction si;
    EXPECT_TRUE(accel.intersect(r, si));
    return si;
}

struct FakeBSDF : BSDF {
    std::pair<BSDFSample, Color3> sample(const BSDFContext&, const SurfaceInteraction&, float,
                                         Point2f) const override {
        return {};
    }
    Color3 eval(const BSDFContext&, const SurfaceInteraction&, const Vec3f&) const override {
        return Color3(0.f);
    }
    float pdf(const BSDFContext&, const SurfaceInteraction&, const Vec3f&) const override { return 0.f; }
};

struct FakeEmitter : Emitter {
    explicit FakeEmitter(uint32_t flags) { flags_ = flags; }
    std::pair<DirectionSample, Color3> sample_direction(const Interaction&, Point2f) const override {
        return {};
    }
    float pdf_direction(const Interaction&, const DirectionSample&) const override { return 0.f; }
    Color3 eval(const SurfaceInteraction&) const override { return Color3(0.f); }
    RaySample sample_ray(Point2f, Point2f) const override { return {}; }
    Color3 power() const override { return Color3(0.f); }
};

}  // namespace

TEST(ShapeRectangle, UvNormalFrame) {
    auto r = make_shape(
        ShapeProps("rectangle").t("to_world", Transform::translate({0, 0, 1}) * Transform::scale({2, 3, 1})));
    SurfaceInteraction si = trace(*r, Ray({1, -1.5f, 5}, {0, 0, -1}));
    EXPECT_NEAR(si.t, 4.f, 1e-5f);
    EXPECT_NEAR(si.uv.x, 0.75f, 1e-5f);  // object x = 0.5
    EXPECT_NEAR(si.uv.y, 0.25f, 1e-5f);  // object y = -0.5
    EXPECT_NEAR(si.n.z, 1.f, 1e-6f);
    EXPECT_NEAR(si.sh_frame.s.x, 1.f, 1e-6f);  // tangent along dp/du = +x
    EXPECT_NEAR(si.sh_frame.t.y, 1.f, 1e-6f);
    EXPECT_NEAR(r->surface_area(), 24.f, 1e-5f);
    const TriangleMesh* m = r->triangle_mesh();
    ASSERT_NE(m, nullptr);
    EXPECT_TRUE(m->normals.empty());
}

TEST(ShapeRectangle, MirroredTransformKeepsMitsubaNormal) {
    // Mitsuba's rectangle transforms its normal with the inverse transpose: scale(-1,1,1) keeps +z.
    auto r = make_shape(ShapeProps("rectangle").t("to_world", Transform::scale({-1, 1, 1})));
    SurfaceInteraction si = trace(*r, Ray({0.5f, 0.5f, 1}, {0, 0, -1}));
    EXPECT_NEAR(si.n.z, 1.f, 1e-6f);
    EXPECT_NEAR(si.uv.x, 0.25f, 1e-6f);  // object x = -0.5
    EXPECT_NEAR(r->sample_position({0.3f, 0.7f}).n.z, 1.f, 1e-6f);
}

TEST(ShapeRectangle, FlipNormalsAndNoFaceNormalsParameter) {
    auto r = make_shape(ShapeProps("rectangle").b("flip_normals", true));
    EXPECT_NEAR(trace(*r, Ray({0, 0, 1}, {0, 0, -1})).n.z, -1.f, 1e-6f);
    EXPECT_NEAR(r->sample_position({0.5f, 0.5f}).n.z, -1.f, 1e-6f);
    EXPECT_THROW(make_shape(ShapeProps("rectangle").b("face_normals", true)), InputError);
}

TEST(ShapeCube, MitsubaLayout) {
    auto c = make_shape(ShapeProps("cube"));
    const TriangleMesh* m = c->triangle_mesh();
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(m->positions.size(), 24u);
    EXPECT_EQ(m->triangle_count(), 12u);
    // +z face (Mitsuba's vertices 12..15: (1,-1,1) (1,1,1) (-1,1,1) (-1,-1,1) with uvs (0,1) (1,1) (1,0)
    // (0,0)).
    SurfaceInteraction si = trace(*c, Ray({0.5f, -0.5f, 5}, {0, 0, -1}));
    EXPECT_NEAR(si.n.z, 1.f, 1e-6f);
    EXPECT_NEAR(si.sh_frame.n.z, 1.f, 1e-6f);
    // On this face u = (y+1)/2 and v = (x+1)/2: (x, y) = (0.5, -0.5) -> (0.25, 0.75).
    EXPECT_NEAR(si.uv.x, 0.25f, 1e-5f);
    EXPECT_NEAR(si.uv.y, 0.75f, 1e-5f);
    EXPECT_NEAR(c->surface_area(), 24.f, 1e-5f);
    // flip_normals and face_normals are accepted.
    auto flipped = make_shape(ShapeProps("cube").b("flip_normals", true).b("face_normals", true));
    EXPECT_NEAR(trace(*flipped, Ray({0.5f, -0.5f, 5}, {0, 0, -1})).n.z, -1.f, 1e-6f);
}

TEST(ShapeCommon, DefaultDirectionSamplingConvertsAreaPdf) {
    auto r = make_shape(ShapeProps("rectangle"));  // area 4, normal +z
    Interaction ref;
    ref.p = {0.3f, -0.2f, 2.f};
    DirectionSample ds = r->sample_direction(ref, {0.25f, 0.75f});
    Vec3f to = ds.p - ref.p;
    EXPECT_NEAR(ds.dist, norm(to), 1e-6f);
    float cos_light = std::abs(ds.d.z);
    EXPECT_NEAR(ds.pdf, 0.25f * ds.dist * ds.dist / cos_light, 1e-5f);
    EXPECT_NEAR(r->pdf_direction(ref, ds), ds.pdf, 1e-5f);
    // Grazing: zero cosine gives zero pdf rather than infinity.
    DirectionSample graze = ds;
    graze.d = {1, 0, 0};
    EXPECT_EQ(r->pdf_direction(ref, graze), 0.f);
}

TEST(ShapeCommon, BsdfAndEmitterChildren) {
    auto bsdf = std::make_shared<FakeBSDF>();
    auto area = std::make_shared<FakeEmitter>(emitter_flags::Surface);
    ShapeProps sp("sphere");
    sp.set("", "bsdf", ObjectPtr(bsdf));
    sp.set("", "emitter", ObjectPtr(area));
    auto s = make_shape(sp);
    EXPECT_EQ(s->bsdf(), bsdf.get());
    EXPECT_EQ(s->emitter(), area.get());
    EXPECT_EQ(area->shape(), s.get());
    EXPECT_TRUE(s->is_emitter());
    // Sampled directions carry the emitter.
    Interaction ref;
    ref.p = {0, 0, 5};
    EXPECT_EQ(s->sample_direction(ref, {0.5f, 0.5f}).emitter, area.get());
}

TEST(ShapeCommon, ChildErrors) {
    {
        ShapeProps sp("rectangle");
        sp.set("", "bsdf", ObjectPtr(std::make_shared<FakeBSDF>()));
        sp.set("", "bsdf", ObjectPtr(std::make_shared<FakeBSDF>()));
        EXPECT_THROW(make_shape(sp), InputError);
    }
    {
        ShapeProps sp("rectangle");
        sp.set("", "emitter", ObjectPtr(std::make_shared<FakeEmitter>(emitter_flags::DeltaPosition)));
        EXPECT_THROW(make_shape(sp), InputError);  // not an area emitter
    }
    {
        ShapeProps sp("rectangle");
        sp.set("", "bsdf", ObjectPtr(std::make_shared<FakeEmitter>(emitter_flags::Surface)));
        EXPECT_THROW(make_shape(sp), InputError);  // wrong kind
    }
    EXPECT_THROW(make_shape(ShapeProps("teapot")), InputError);
}
