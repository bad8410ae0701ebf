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

// The allocation learned while rendering (issue 59): the passes' statistics are exact sums, the fit a
// pure function of them, and the exploration coins hashes of where each decision is: the same image
// for any thread count. 24 spp (passes of 1, 1, 2, 4, 8, 8): the coarse stage decides after 4 spp, the
// passes after it render with allocations fitted on the full field.
TEST(Determinism, AllocationSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="200000"/>)", "determinism-allocation", "24"),
                         "guided fogbox, the allocation learned while rendering");
}

// Refinement during the render (issue 39): without a time budget the schedule reads only the passes'
// noise, a pure function of the samples, and the further photon pass is traced and added in photon and
// leaf order. 24 spp (passes of 1, 1, 2, 4, 8, 8): the first refinement follows the pass ending at 16
// spp, and the last pass renders with the refined field.
TEST(Determinism, RefinementSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="200000"/><integer name="refine_passes" value="2"/>)",
                                       "determinism-refine", "24"),
                         "guided fogbox, refine_passes");
}

// rrs=ears (issue 38): the continuation statistics are exact sums, frozen between passes, so the
// decisions, and the image, do not depend on the thread count. 8 spp: statistics after the passes of
// 1, 1 and 2 spp, decisions in the passes after them (ears_min_samples 4).
TEST(Determinism, EarsSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="200000"/><string name="rrs" value="ears"/>)"
                                       R"(<integer name="ears_min_samples" value="4"/>)",
                                       "determinism-ears"),
                         "guided fogbox, rrs=ears");
}

// Issue 37: distance="vsp" (one decision per segment from the vertex's leaf).
TEST(Determinism, VspDistanceSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_fogbox(R"(<integer name="photons" value="200000"/><string name="distance" value="vsp"/>)",
                                       "determinism-vsp"),
                         "guided fogbox, distance=vsp");
}

// ... in the heterogeneous cloud: the resampled segment decision (a data-dependent number of
// tentative collisions per segment).
TEST(Determinism, VspResampledSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_bench_scene("cloud", R"(<integer name="photons" value="200000"/><string name="distance" value="vsp"/>)",
                                            "determinism-vsp-cloud"),
                         "guided cloud, distance=vsp");
}


// ... and on the benchmark's dense sphere, where the coarse stage may end the training (the rest
// rendered unguided).
TEST(Determinism, AllocationOnADenseMediumSameImageForOneAndTwoThreads) {
    expect_deterministic(guided_bench_scene("densesphere", R"(<integer name="photons" value="200000"/>)",
                                            "determinism-allocation-dense", "24"),
                         "guided densesphere, the allocation");
}
