// volpath's walk, its policy interface (walk_policy.h) and its recorder interface
// (path_recorder.h): the default policy makes the unguided decisions with exactly the random numbers
// of the walk without a policy, and a recorder sees every contribution the walk adds and every
// medium vertex it scatters at, without changing a number.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "volguide/integrators/camera_sample.h"
#include "volguide/integrators/volpath/volpath.h"
#include "volguide/integrators/volpath/path_recorder.h"
#include "volguide/integrators/volpath/walk_policy.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

using namespace volguide;

namespace {

std::unique_ptr<Scene> load_bench_scene(const std::string& name) {
    LoadOptions options;
    options.defines = {{"width", "8"}, {"height", "6"}, {"spp", "1"}};
    return load_scene(std::string(VOLGUIDE_SOURCE_DIR) + "/bench/scenes/" + name + ".xml", options);
}

// Records what the walk reports (with `decisions`: also the policy's decisions).
class CountingRecorder final : public PathRecorder {
  public:
    explicit CountingRecorder(bool decisions = false) : decisions_(decisions) {}
    void record_contribution(const Color3& value) override {
        contributions += value;
        ++contribution_calls;
    }
    void record_medium_hit(const MediumInteraction&) override { ++medium_hits; }
    void record_medium_vertex(const Point3f&, const Vec3f&, float pdf, const Color3&) override {
        ++vertices;
        EXPECT_GT(pdf, 0.f);
    }
    bool records_decisions() const override { return decisions_; }
    void record_decision(DecisionKind, const DecisionRecord& record) override {
        EXPECT_FALSE(record.mixture);  // the default policy samples no mixture
        ++decisions;
    }
    void record_continuation(ContinuationStage, const Continuation& c, const Vec3f&, const Color3&) override {
        ++continuations;
        if (c.estimate > 0.f) ++estimated;
    }
    void end_camera_sample(int branches) override {
        EXPECT_EQ(branches, 1);  // no continuation decision: never a copy
        ++camera_samples;
    }
    Color3 contributions{0.f};
    int contribution_calls = 0, medium_hits = 0, vertices = 0, camera_samples = 0, decisions = 0, continuations = 0,
        estimated = 0;

  private:
    bool decisions_;
};

bool same_color_bits(const Color3& a, const Color3& b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

// One camera ray walked without a policy or recorder (stream a) and with `policy` and `recorder`
// (either may be null; stream b, a copy of a).
struct TwoWalks {
    Color3 plain, with_policy;
    bool same_dimension;  // both walks drew as many numbers
};
TwoWalks walk_twice(const Scene& scene, const VolPathIntegrator& volpath, const Ray& ray, Sampler& a, Sampler& b,
                    WalkPolicy* policy, PathRecorder* recorder) {
    TwoWalks w;
    w.plain = volpath.walk(scene, a, ray, nullptr);
    w.with_policy = volpath.walk(scene, b, ray, policy, recorder);
    w.same_dimension = a.next_1d() == b.next_1d();
    return w;
}

VolPathIntegrator volpath_with(bool equiangular) {
    VolPathSettings settings;
    settings.max_depth = 32;
    settings.equiangular = equiangular;
    return VolPathIntegrator(settings);
}

// Calls check(ray, a, b) for every pixel's first `spp` camera samples of `scene`, with two copies
// of the sample's stream.
template <typename Check>
void for_each_sample(const Scene& scene, const VolPathIntegrator& volpath, int spp, Check&& check) {
    const Film& film = scene.sensor().film();
    const FilmGrid grid{film.width(), film.height(), 0};
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x)
            for (int s = 0; s < spp; ++s) {
                FilmSample a = film_sample(grid, 5, x, y, uint64_t(s));
                FilmSample b = a;
                const Ray ray = scene.sensor().sample_ray(a.film_uv, Point2f(0.5f, 0.5f)).first;
                check(ray, a.sampler, b.sampler);
            }
}

}  // namespace

TEST(WalkPolicy, DefaultPolicyIsTheAnalogWalkNumberForNumber) {
    for (const char* name : {"fogbox", "sss", "cloud"}) {
        auto scene = load_bench_scene(name);
        for (bool equiangular : {false, true}) {
            const VolPathIntegrator volpath = volpath_with(equiangular);
            int differ = 0, nonzero = 0;
            for_each_sample(*scene, volpath, 4, [&](const Ray& ray, Sampler& a, Sampler& b) {
                WalkPolicy unguided;
                const TwoWalks w = walk_twice(*scene, volpath, ray, a, b, &unguided, nullptr);
                differ += !same_color_bits(w.plain, w.with_policy) || !w.same_dimension;
                nonzero += w.plain.max_value() > 0.f;
            });
            EXPECT_EQ(differ, 0) << name << (equiangular ? " equiangular" : "");
            EXPECT_GT(nonzero, 10) << name;
        }
    }
}

TEST(WalkPolicy, RecordingSeesEveryContributionAndMediumVertex) {
    auto scene = load_bench_scene("fogbox");
    const VolPathIntegrator volpath = volpath_with(false);
    int vertices = 0, samples = 0;
    for_each_sample(*scene, volpath, 4, [&](const Ray& ray, Sampler& a, Sampler& b) {
        // A recorder alone, then beside the default policy (stream b replayed from a copy).
        Sampler b2 = b;
        CountingRecorder alone;
        const TwoWalks w = walk_twice(*scene, volpath, ray, a, b, nullptr, &alone);
        WalkPolicy unguided;
        CountingRecorder recorder;
        Sampler a2 = b2;
        const TwoWalks w2 = walk_twice(*scene, volpath, ray, a2, b2, &unguided, &recorder);
        for (const auto& [walks, rec] : {std::pair{&w, &alone}, std::pair{&w2, &recorder}}) {
            EXPECT_TRUE(same_color_bits(walks->plain, walks->with_policy) && walks->same_dimension);
            // The same additions in the same order: the same sum.
            EXPECT_TRUE(same_color_bits(rec->contributions, walks->with_policy));
            EXPECT_EQ(rec->camera_samples, 1);
            EXPECT_GE(rec->medium_hits, rec->vertices);  // a vertex is reached before it scatters
            EXPECT_EQ(rec->decisions, 0);  // the recorder does not read decisions
        }
        EXPECT_EQ(alone.vertices, recorder.vertices);
        vertices += recorder.vertices;
        ++samples;
    });
    EXPECT_GT(vertices, samples / 4);  // the fog scatters: vertices were reported
}

// A recorder that reads decisions gets one report per sampling decision of the policy, none
// without a policy, and the walk still draws the same numbers.
TEST(WalkPolicy, DecisionReadingRecorderSeesEveryPolicyDecision) {
    auto scene = load_bench_scene("fogbox");
    const VolPathIntegrator volpath = volpath_with(false);
    int decisions = 0;
    for_each_sample(*scene, volpath, 4, [&](const Ray& ray, Sampler& a, Sampler& b) {
        Sampler b2 = b;
        CountingRecorder without_policy(true);
        const TwoWalks w = walk_twice(*scene, volpath, ray, a, b, nullptr, &without_policy);
        EXPECT_TRUE(same_color_bits(w.plain, w.with_policy) && w.same_dimension);
        EXPECT_EQ(without_policy.decisions, 0);
        WalkPolicy unguided;
        CountingRecorder recorder(true);
        Sampler a2 = b2;
        const TwoWalks w2 = walk_twice(*scene, volpath, ray, a2, b2, &unguided, &recorder);
        EXPECT_TRUE(same_color_bits(w2.plain, w2.with_policy) && w2.same_dimension);
        // Every medium vertex had a distance and a direction decision (the last may have ended the
        // path); every vertex reached is a continuation point, and the default continuation reports
        // no estimate.
        EXPECT_GE(recorder.decisions, 2 * recorder.vertices);
        EXPECT_GE(recorder.continuations, recorder.vertices);
        EXPECT_EQ(recorder.estimated, 0);
        decisions += recorder.decisions;
    });
    EXPECT_GT(decisions, 0);
}
