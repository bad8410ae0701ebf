// The Open PGL path recorder (src/volguide/integrators/openpgl/openpgl_path_recorder.h) on a hand-made path:
// the samples Open PGL's PrepareSamples makes from its segments carry, at each scattering vertex,
// the radiance recorded after it divided by the throughput there, over the direction's pdf
// (Open PGL's weight = max channel / pdf), at the distance to the next vertex. Skipped without Open PGL.
#include <gtest/gtest.h>

#if VOLGUIDE_HAVE_OPENPGL
#include <algorithm>
#include <cmath>

#include "volguide/integrators/openpgl/openpgl_field.h"
#include "volguide/integrators/openpgl/openpgl_path_recorder.h"

using namespace volguide;

namespace {

OpenPglPathRecorder::Vertex medium_vertex(Point3f x, Vec3f wo, float pdf, float throughput) {
    OpenPglPathRecorder::Vertex v;
    v.x = x;
    v.wo = wo;
    v.wi = Vec3f(-1.f, 0.f, 0.f);
    v.pdf = pdf;
    v.throughput = Color3(throughput);
    v.volume = true;
    return v;
}

}  // namespace

TEST(OpenPglPathRecorder, SamplesCarryTheIncidentRadianceOverThePdf) {
    OpenPglField field(BBox3f(Point3f(-10.f), Point3f(10.f)), 1, 32000);
    OpenPglPathRecorder rec;
    rec.begin_path();
    // Vertex 0 at the origin, sampled towards +x with pdf 0.25, throughput 0.5 after it.
    rec.reached(Point3f(0.f));
    rec.add_vertex(medium_vertex(Point3f(0.f), Vec3f(1.f, 0.f, 0.f), 0.25f, 0.5f));
    // Vertex 1 two units along +x: its NEE adds 0.1 (radiance arriving at vertex 0), then it samples
    // +y with pdf 0.5, throughput 0.25 after it.
    rec.reached(Point3f(2.f, 0.f, 0.f));
    rec.add_contribution(Color3(0.1f, 0.05f, 0.02f));
    rec.add_vertex(medium_vertex(Point3f(2.f, 0.f, 0.f), Vec3f(0.f, 1.f, 0.f), 0.5f, 0.25f));
    // The path hits an emitter three units along +y and ends: 0.05 more.
    rec.reached(Point3f(2.f, 3.f, 0.f));
    rec.add_contribution(Color3(0.05f, 0.04f, 0.01f));
    rec.end_path(field);

    const openpgl::cpp::SampleStorage& s = field.pending_samples();
    ASSERT_EQ(s.GetSizeVolume(), 2u);
    EXPECT_EQ(s.GetSizeSurface(), 0u);
    // Sample order is Open PGL's (last vertex first); find each by its direction.
    for (size_t i = 0; i < 2; ++i) {
        const openpgl::cpp::SampleData d = s.GetSampleVolume(int(i));
        if (d.direction.x > 0.5f) {  // vertex 0: L = (0.1 + 0.05, ...) / 0.5, max channel 0.3
            EXPECT_NEAR(d.weight, 0.3f / 0.25f, 1e-5f);
            EXPECT_NEAR(d.pdf, 0.25f, 1e-6f);
            EXPECT_NEAR(d.distance, 2.f, 1e-5f);
        } else {  // vertex 1: L = 0.05 / 0.25 = 0.2
            EXPECT_NEAR(d.weight, 0.2f / 0.5f, 1e-5f);
            EXPECT_NEAR(d.distance, 3.f, 1e-5f);
            EXPECT_NEAR(d.position.x, 2.f, 1e-6f);
        }
    }
}

// The same path reported the way volpath's walk reports it (path_recorder.h): the medium vertex's
// hit before its direction, the vertex after it, the surface hit that ends the path.
TEST(OpenPglPathRecorder, WalkReportsMakeTheSameSamples) {
    OpenPglField field(BBox3f(Point3f(-10.f), Point3f(10.f)), 1, 32000);
    OpenPglPathRecorder rec;
    PathRecorder& walk = rec;
    rec.begin_path();
    MediumInteraction mi;
    mi.p = Point3f(0.f);
    mi.wi = Vec3f(-1.f, 0.f, 0.f);
    walk.record_medium_hit(mi);
    walk.record_medium_vertex(mi.p, Vec3f(1.f, 0.f, 0.f), 0.25f, Color3(0.5f));
    mi.p = Point3f(2.f, 0.f, 0.f);
    walk.record_medium_hit(mi);
    walk.record_contribution(Color3(0.1f, 0.05f, 0.02f));
    walk.record_medium_vertex(mi.p, Vec3f(0.f, 1.f, 0.f), 0.5f, Color3(0.25f));
    SurfaceInteraction hit;
    walk.record_surface_hit(hit);  // left the scene: the closing segment goes far along +y
    walk.record_contribution(Color3(0.05f, 0.04f, 0.01f));
    rec.end_path(field);

    const openpgl::cpp::SampleStorage& s = field.pending_samples();
    ASSERT_EQ(s.GetSizeVolume(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        const openpgl::cpp::SampleData d = s.GetSampleVolume(int(i));
        if (d.direction.x > 0.5f) {
            EXPECT_NEAR(d.weight, 0.3f / 0.25f, 1e-5f);
            EXPECT_NEAR(d.distance, 2.f, 1e-5f);
        } else {
            EXPECT_NEAR(d.weight, 0.2f / 0.5f, 1e-5f);
            EXPECT_NEAR(d.position.x, 2.f, 1e-6f);
        }
    }
}

#else

TEST(OpenPglPathRecorder, SamplesCarryTheIncidentRadianceOverThePdf) {
    GTEST_SKIP() << "volguide was built without Intel Open PGL";
}

#endif
