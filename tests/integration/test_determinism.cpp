// One seed gives a bit-identical image for any thread count (issue 2), for the surface demo, the
// volumetric demo (media spend a data-dependent number of random numbers per path) and
// guided_volpath with its trained field.
#include <gtest/gtest.h>

#include "support/cli.h"
#include "support/test_support.h"

using namespace volguide::test;

namespace {

// Renders `scene` with `defines` at 1 and 2 threads (same seed) and with another seed; returns the
// three EXR files' bytes.
struct Renders {
    std::string one_thread, two_threads, other_seed;
};
Renders render_three(const std::string& scene, const std::vector<std::string>& defines, const std::string& tag,
                     const std::string& spp = "8") {
    TempDir dir(tag);
    auto run = [&](const std::string& seed, const std::string& threads, const std::string& out) {
        std::vector<std::string> args = {"render", scene, "--spp", spp, "--seed", seed, "--threads", threads,
                                         "--quiet", "-o", dir.file(out)};
        for (const std::string& d : defines) args.insert(args.end(), {"-D", d});
        CliResult r = run_cli(args);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return read_file(dir.file(out));
    };
    return {run("11", "1", "t1.exr"), run("11", "2", "t2.exr"), run("12", "2", "t3.exr")};
}

void expect_deterministic(const Renders& r, const std::string& what) {
    EXPECT_FALSE(r.one_thread.empty()) << what;
    EXPECT_TRUE(r.one_thread == r.two_threads) << what << ": images differ between 1 and 2 threads";
    // A different seed must change the image (the comparison above can fail).
    EXPECT_FALSE(r.other_seed == r.one_thread) << what << ": the seed has no effect";
}

// render_three on the benchmark scene `bench_scene` at 32x24 with guided_volpath and the integrator
// parameters `params` (XML elements).
Renders guided_bench_scene(const std::string& bench_scene, const std::string& params, const std::string& tag,
                           const std::string& spp = "8") {
    TempDir dir(tag + "-settings");
    const std::string integrator = dir.write(
        "integrator.xml",
        R"(<scene version="3.0.0"><integrator type="guided_volpath"><integer name="max_depth" value="$max_depth"/>)" +
            params + "</integrator></scene>");
    return render_three(source_dir() + "/bench/scenes/" + bench_scene + ".xml",
                        {"width=32", "height=24", "integrator=guided_volpath", "integrator_xml=" + integrator}, tag,
                        spp);
}

// ... on the benchmark's fog-filled Cornell box.
Renders guided_fogbox(const std::string& params, const std::string& tag, const std::string& spp = "8") {
    return guided_bench_scene("fogbox", params, tag, spp);
}

}  // namespace

TEST(Determinism, SameSeedSameImageForOneAndTwoThreads) {
    const std::string scene = source_dir() + "/scenes/demo/cornell-box.xml";
    for (const char* filter : {"box", "gaussian"})
        expect_deterministic(render_three(scene, {"res=48", std::string("filter=") + filter}, "determinism"),
                             std::string("cornell box, filter ") + filter);
}

TEST(Determinism, VolumetricDemoSameImageForOneAndTwoThreads) {
    const std::string scene = source_dir() + "/scenes/demo/light-shafts.xml";
    expect_deterministic(render_three(scene, {"width=40", "height=24"}, "determinism-volume"), "light shafts");
}

// guided_volpath's full guided system (photon training, guided distances, product directions in the
// fog and at the walls) on the benchmark's fog-filled Cornell box: the field and every guided
// decision depend on the seed only. 300 k photons (74 batches in 5 waves, kd-tree subtrees far above
// parallel_min_samples, so every parallel step of the training runs) instead of the default 1 M: the
// same code in a third of the time, which matters under ThreadSanitizer (CI runs it there).
TEST(Determinism, GuidedSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="300000"/>)", "determinism-guided"),
                         "guided fogbox");
}

// Learned selection's pilot and fit (exact sums) on the same scene: the same image for any thread count.
TEST(Determinism, LearnedSelectionSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="200000"/><integer name="selection_spp" value="2"/>)"
                                       R"(<integer name="selection_min_samples" value="8"/>)",
                                       "determinism-selection"),
                         "guided fogbox, learned selection");
}

// Online learning (online_spp): each pass's recorded paths are joined in stream-key order before the
// field is rebuilt, so the fields, and the image, do not depend on the thread count. 8 spp with
// online_spp 4: updates after the passes of 1, 1 and 2 spp, then a pass with the last field.
TEST(Determinism, OnlineLearningSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<string name="training" value="progressive"/><integer name="training_iterations" value="3"/>)"
                                       R"(<integer name="online_spp" value="4"/><integer name="leaf_samples" value="400"/>)",
                                       "determinism-online"),
                         "guided fogbox, online learning");
}

// Refinement during the render (issue 39): without a time budget the schedule reads only the passes'
// noise, a pure function of the samples, and the further photon pass is traced and added in photon and
// leaf order. 24 spp (passes of 1, 1, 2, 4, 8, 8): the pass ending at 4 spp fixes the noise's normaliser,
// the one ending at 8 measures it and a refinement follows; at 16 the schedule judges it.
TEST(Determinism, RefinementSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="200000"/><integer name="refine_passes" value="2"/>)"
                                       R"(<integer name="refine_spp" value="2"/><float name="refine_gain" value="0"/>)",
                                       "determinism-refine", "24"),
                         "guided fogbox, refine_passes");
}

// guide_target=variance (docs/theory.md §23): each leaf's weights are refitted sequentially over its
// samples in input order, in the training's rebuilds and the online updates alike.
TEST(Determinism, VarianceAwareTargetSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<string name="training" value="progressive"/><integer name="training_iterations" value="3"/>)"
                                       R"(<integer name="online_spp" value="4"/><integer name="leaf_samples" value="400"/>)"
                                       R"(<string name="guide_target" value="variance"/>)",
                                       "determinism-variance"),
                         "guided fogbox, variance-aware target");
}

// rrs=ears (issue 38): the continuation statistics are exact sums, frozen between passes, so the
// decisions, and the image, do not depend on the thread count. 8 spp: statistics after the passes of
// 1, 1 and 2 spp, decisions in the passes after them (ears_min_samples 4); after 2 spp half the camera
// samples are recorded (chosen by their sampler keys).
TEST(Determinism, EarsSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="200000"/><string name="rrs" value="ears"/>)"
                                       R"(<integer name="ears_min_samples" value="4"/><integer name="ears_record_spp" value="2"/>)"
                                       R"(<float name="ears_record_fraction" value="0.5"/>)",
                                       "determinism-ears"),
                         "guided fogbox, rrs=ears");
}

// Issue 37: distance="vsp" (one decision per segment from the vertex's leaf).
TEST(Determinism, VspDistanceSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="200000"/><string name="distance" value="vsp"/>)",
                                       "determinism-vsp"),
                         "guided fogbox, distance=vsp");
}

// ... with the equiangular share of the conditional distance (a light point drawn per scatter,
// docs/theory.md §7.10.1) at 0.5 and 1.
TEST(Determinism, VspEquiangularSameImageForOneAndTwoThreads) {
    for (const char* e : {"0.5", "1"})
        expect_deterministic(guided_fogbox(std::string(R"(<integer name="photons" value="200000"/><string name="distance" value="vsp"/>)"
                                                       R"(<float name="vsp_equiangular" value=")") + e + R"("/>)",
                                           "determinism-vsp-equi"),
                             std::string("guided fogbox, distance=vsp, vsp_equiangular=") + e);
}

// ... in the heterogeneous cloud: the resampled segment decision (a data-dependent number of
// tentative collisions per segment).
TEST(Determinism, VspResampledSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_bench_scene("cloud", R"(<integer name="photons" value="200000"/><string name="distance" value="vsp"/>)",
                                            "determinism-vsp-cloud"),
                         "guided cloud, distance=vsp");
}

// Issue 37 deliverable 4: distance="vsp_product" and the per-cell distance method chosen from the
// pilot's rounds (counted lookups, exact sums): the same image for any thread count.
TEST(Determinism, VspProductAndMethodChoiceSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="200000"/><string name="distance" value="vsp_product"/>)",
                                       "determinism-vsp-product"),
                         "guided fogbox, distance=vsp_product");
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="200000"/><string name="distance" value="vsp"/>)"
                                       R"(<integer name="selection_spp" value="2"/><integer name="selection_min_samples" value="8"/>)"
                                       R"(<boolean name="selection_distance_method" value="true"/>)",
                                       "determinism-method-choice"),
                         "guided fogbox, per-cell distance method");
    // Guided vertices made dear: the cells fall back to volpath (its decisions and throughput roulette).
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="200000"/><string name="distance" value="vsp"/>)"
                                       R"(<integer name="selection_spp" value="2"/><integer name="selection_min_samples" value="8"/>)"
                                       R"(<boolean name="selection_distance_method" value="true"/>)"
                                       R"(<float name="selection_cost_ns_guided_direction" value="1e7"/>)",
                                       "determinism-method-volpath"),
                         "guided fogbox, per-cell method with volpath cells");
}
