// TrainingRecorder's suffix-radiance bookkeeping (training_recorder.h) on a synthetic path, and the
// PerSampleMean fluence of a leaf with NEE samples (count 0).
#include <gtest/gtest.h>

#include "volguide/guiding/guiding_field.h"
#include "volguide/integrators/guided/training/training_recorder.h"

using namespace volguide;

TEST(TrainingRecorder, SuffixRadianceOverThroughputAndPdf) {
    TrainingRecorder rec;
    rec.record_contribution(Color3(100.f));  // seen directly by the camera: no vertex to credit
    rec.record_medium_vertex(Point3f(1.f, 0.f, 0.f), Vec3f(1.f, 0.f, 0.f), 0.25f, Color3(0.5f, 0.5f, 0.f));
    rec.record_contribution(Color3(1.f, 2.f, 3.f));  // e.g. the emitter hit after vertex 0
    rec.record_medium_nee(Point3f(2.f, 0.f, 0.f), Vec3f(0.f, 1.f, 0.f), Color3(7.f));
    rec.record_contribution(Color3(0.5f));  // NEE at vertex 1: credited to vertex 0 only
    rec.record_medium_vertex(Point3f(2.f, 0.f, 0.f), Vec3f(0.f, 0.f, 1.f), 0.5f, Color3(0.25f));
    rec.record_contribution(Color3(0.25f));
    rec.record_medium_nee(Point3f(3.f, 0.f, 0.f), Vec3f(0.f, 1.f, 0.f), Color3(0.f));  // zero: dropped
    std::vector<RadianceSample> out;
    rec.finish(out);
    ASSERT_EQ(out.size(), 3u);
    // Vertex 0: (1,2,3) + 0.5 + 0.25 over throughput (0.5, 0.5, 0) and pdf 0.25; no blue throughput.
    EXPECT_FLOAT_EQ(out[0].weight.r, 1.75f / 0.5f / 0.25f);
    EXPECT_FLOAT_EQ(out[0].weight.g, 2.75f / 0.5f / 0.25f);
    EXPECT_EQ(out[0].weight.b, 0.f);
    EXPECT_EQ(out[0].direction, Vec3f(1.f, 0.f, 0.f));
    EXPECT_EQ(out[0].count, 1.f);
    // Its second moment L^2 / p, the channel mean of the squares (docs/theory.md §23.3).
    const float L0r = 1.75f / 0.5f, L0g = 2.75f / 0.5f;
    EXPECT_FLOAT_EQ(out[0].second_moment, (L0r * L0r + L0g * L0g) / 3.f / 0.25f);
    // Vertex 1: only what came after it.
    EXPECT_FLOAT_EQ(out[1].weight.r, 0.25f / 0.25f / 0.5f);
    EXPECT_FLOAT_EQ(out[1].second_moment, 1.f / 0.5f);  // L^ = 1 in every channel
    EXPECT_EQ(out[1].position, Point3f(2.f, 0.f, 0.f));
    // The NEE sample: its own weight, count 0.
    EXPECT_EQ(out[2].weight, Color3(7.f));
    EXPECT_EQ(out[2].direction, Vec3f(0.f, 1.f, 0.f));
    EXPECT_EQ(out[2].count, 0.f);
    // NEE carries no second moment: the direction decision's estimator does not collect it (§23.3).
    EXPECT_EQ(out[2].second_moment, 0.f);
    // finish() clears: the next path starts empty.
    rec.record_contribution(Color3(1.f));
    rec.finish(out);
    EXPECT_EQ(out.size(), 3u);
}

TEST(TrainingRecorder, ZeroValuedVerticesAreKept) {
    TrainingRecorder rec;
    rec.record_medium_vertex(Point3f(0.f), Vec3f(0.f, 0.f, 1.f), 0.1f, Color3(1.f));
    std::vector<RadianceSample> out;
    rec.finish(out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_TRUE(out[0].weight.is_black());
    EXPECT_EQ(out[0].count, 1.f);
}

TEST(GuidingFieldPerSampleMean, NeeSamplesDoNotCountAsVertices) {
    std::vector<RadianceSample> samples;
    for (int i = 0; i < 100; ++i) {
        samples.push_back({Point3f(0.5f), Vec3f(0.f, 0.f, 1.f), Color3(2.f), 1.f});  // vertex
        samples.push_back({Point3f(0.5f), Vec3f(1.f, 0.f, 0.f), Color3(4.f), 0.f});  // its NEE
        samples.push_back({Point3f(0.5f), Vec3f(0.f, 1.f, 0.f), Color3(0.f), 1.f});  // a zero vertex
    }
    GuidingFieldSettings fs;
    fs.fluence = FluenceEstimator::PerSampleMean;
    const GuidingField f = GuidingField::build(BBox3f(Point3f(0.f), Point3f(1.f)), samples, fs);
    ASSERT_EQ(f.leaves().size(), 1u);
    // 200 vertices carrying 100 x (2 + 4) in total.
    EXPECT_FLOAT_EQ(f.leaves()[0].fluence.r, 3.f);
}

// A split path (guided splitting): vertex 0, then two copies made there. The first copy records
// vertex 1 and collects 2; the second resumes at vertex 0, records vertex 2 and collects 3; a copy
// made before any vertex credits nothing. Each vertex's radiance is its subtree's.
TEST(TrainingRecorder, SplitCopiesCreditTheirAncestorsOnly) {
    TrainingRecorder rec;
    const int before_any = rec.branch_point();
    rec.record_medium_vertex(Point3f(0.f), Vec3f(0.f, 0.f, 1.f), 1.f, Color3(1.f));
    rec.record_contribution(Color3(0.5f));  // NEE at vertex 0
    const int at_0 = rec.branch_point();    // the second copy, walked later
    rec.record_medium_vertex(Point3f(1.f), Vec3f(0.f, 0.f, 1.f), 1.f, Color3(0.5f));
    rec.record_contribution(Color3(2.f));
    rec.resume_branch(at_0);
    rec.record_medium_vertex(Point3f(2.f), Vec3f(0.f, 0.f, 1.f), 1.f, Color3(0.5f));
    rec.record_contribution(Color3(3.f));
    rec.resume_branch(before_any);
    rec.record_contribution(Color3(100.f));  // an emitter seen by a copy made before any vertex
    std::vector<RadianceSample> out;
    rec.finish(out);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_FLOAT_EQ(out[0].weight.r, 0.5f + 2.f + 3.f);
    EXPECT_FLOAT_EQ(out[1].weight.r, 2.f / 0.5f);
    EXPECT_FLOAT_EQ(out[2].weight.r, 3.f / 0.5f);
}
