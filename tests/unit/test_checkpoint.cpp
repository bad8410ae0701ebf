// Render checkpoints (integrators/checkpoint_file.h, render_state.h): the file's round trip, its
// refusals (corrupt, truncated, another scene, build, configuration or options), and the render loop
// resumed from the state after any pass rendering the uninterrupted image bit for bit, at another
// thread count (this suite also runs under ThreadSanitizer: the checkpoint callback runs between the
// threaded passes).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>

#include "support/cli.h"
#include "volguide/integrators/checkpoint_file.h"
#include "volguide/integrators/render_loop.h"
#include "volguide/render/sensors/rfilters.h"

namespace volguide {
namespace {

Checkpoint example_checkpoint() {
    Checkpoint c;
    c.identity = {"0123456789abcdef", "scene.xml", "v1-gcc", "volpath[max_depth=8]",
                  {{"spp target", "64"}, {"seed", "7"}, {"resolution", "4x2"}}};
    c.state.passes = 3;
    c.state.spp_done = 4;
    c.state.first_sample = 16;
    c.state.film.weight.assign(8, 0.5);
    c.state.film.sum.assign(24, 1.25);
    c.state.noise_scale.assign(8, 0.75f);
    c.state.samples = 32;
    c.state.nonfinite_samples = 1;
    c.state.integrator = std::string("state\0bytes", 11);
    return c;
}

TEST(Checkpoint, FileRoundTripsExactly) {
    const Checkpoint c = example_checkpoint();
    const Checkpoint back = deserialize_checkpoint(serialize_checkpoint(c));
    EXPECT_EQ(back.identity.scene, c.identity.scene);
    EXPECT_EQ(back.identity.build, c.identity.build);
    EXPECT_EQ(back.identity.options, c.identity.options);
    EXPECT_EQ(back.state.passes, 3);
    EXPECT_EQ(back.state.spp_done, 4);
    EXPECT_EQ(back.state.first_sample, 16u);
    EXPECT_EQ(back.state.film.weight, c.state.film.weight);
    EXPECT_EQ(back.state.film.sum, c.state.film.sum);
    EXPECT_TRUE(back.state.film.sum2.empty());
    EXPECT_EQ(back.state.noise_scale, c.state.noise_scale);
    EXPECT_EQ(back.state.integrator, c.state.integrator);
    EXPECT_EQ(serialize_checkpoint(back), serialize_checkpoint(c));
}

void expect_refused(const std::string& bytes, const std::string& reason) {
    try {
        deserialize_checkpoint(bytes);
        ADD_FAILURE() << "accepted; expected: " << reason;
    } catch (const CheckpointError& e) {
        EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
}

TEST(Checkpoint, CorruptOrTruncatedFilesAreRefused) {
    const std::string bytes = serialize_checkpoint(example_checkpoint());
    std::string flipped = bytes;
    flipped[bytes.size() / 2] ^= 0x10;
    expect_refused(flipped, "checksum");
    expect_refused(bytes.substr(0, bytes.size() - 1), "checksum");
    expect_refused(bytes.substr(0, 30), "checksum");
    expect_refused(bytes.substr(0, 5), "not a volguide checkpoint");
    expect_refused("VGTRAIN" + bytes.substr(7), "not a volguide checkpoint");
}

TEST(Checkpoint, MismatchNamesWhatDiffers) {
    const CheckpointIdentity saved = example_checkpoint().identity;
    EXPECT_EQ(checkpoint_mismatch(saved, saved), "");
    CheckpointIdentity other = saved;
    other.build = "v2-gcc";
    EXPECT_NE(checkpoint_mismatch(saved, other).find("another build (v1-gcc; this one is v2-gcc)"), std::string::npos);
    other = saved;
    other.integrator = "guided_volpath[]";
    EXPECT_NE(checkpoint_mismatch(saved, other).find("integrator configuration"), std::string::npos);
    other = saved;
    other.scene = "fedcba9876543210";
    EXPECT_NE(checkpoint_mismatch(saved, other).find("another scene (scene.xml"), std::string::npos);
    other = saved;
    other.options[1].second = "8";
    EXPECT_EQ(checkpoint_mismatch(saved, other), "written with seed 7 (this render: 8)");
    other = saved;
    other.options.emplace_back("variance", "on");
    EXPECT_EQ(checkpoint_mismatch(saved, other), "written with variance (none) (this render: on)");
}

TEST(Checkpoint, SavingReplacesTheFileWholeOrNotAtAll) {
    test::TempDir dir("checkpoint-save");
    const std::string path = dir.file("render.ckpt");
    Checkpoint c = example_checkpoint();
    save_checkpoint(path, c);
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    EXPECT_EQ(load_checkpoint(path).state.spp_done, 4);
    c.state.spp_done = 8;
    save_checkpoint(path, c);
    EXPECT_EQ(load_checkpoint(path).state.spp_done, 8);
    // A save that cannot complete (its temporary file cannot be made) throws and leaves nothing.
    EXPECT_THROW(save_checkpoint(dir.file("missing/render.ckpt"), c), CheckpointError);
    EXPECT_FALSE(std::filesystem::exists(dir.file("missing")));
    EXPECT_THROW(load_checkpoint(dir.file("none.ckpt")), CheckpointError);
}

bool same_bits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(Color3)) == 0;
}

Color3 signal(Point2f uv, Sampler& s) {
    const float a = s.next_1d(), b = s.next_1d();
    return Color3(uv.x + a, uv.y * b * b, std::cos(7.f * uv.y) + a);
}

// Every pass's state (final: false) and each pass's reported noise.
struct Recorded {
    std::vector<RenderState> states;
    std::vector<double> noise;
    int finals = 0;
};

RenderOptions recording(Recorded& rec, int spp, int threads) {
    RenderOptions opt;
    opt.spp = spp;
    opt.first_sample = 5;
    opt.tile_size = 8;
    opt.threads = threads;
    opt.checkpoint = [&rec](const std::function<RenderState()>& state, bool final) {
        if (final)
            ++rec.finals;
        else
            rec.states.push_back(state());
    };
    opt.end_pass = [&rec](const PassReport& pass) { rec.noise.push_back(pass.relative_variance); };
    return opt;
}

TEST(Checkpoint, ResumedRenderFrameIsBitIdenticalForAnyThreadCount) {
    GaussianFilter filter;
    const FrameSetup setup{29, 17, &filter, true, 4, 3, true};
    Recorded full;
    const RenderResult uninterrupted = render_frame(setup, signal, recording(full, 37, 2));
    ASSERT_EQ(full.states.size(), pass_schedule(37).size());
    EXPECT_EQ(full.finals, 1);
    for (size_t k : {size_t(0), size_t(2), size_t(3), size_t(5)}) {
        Recorded rest;
        RenderOptions opt = recording(rest, 37, k % 2 ? 1 : 3);
        const RenderState state = deserialize_render_state(serialize_render_state(full.states[k]));
        opt.resume = &state;
        const RenderResult resumed = render_frame(setup, signal, opt);
        EXPECT_EQ(resumed.spp, 37);
        EXPECT_EQ(resumed.stats.passes, uninterrupted.stats.passes);
        EXPECT_EQ(resumed.stats.samples, uninterrupted.stats.samples);
        EXPECT_TRUE(same_bits(resumed.mean, uninterrupted.mean)) << "resumed after pass " << k;
        EXPECT_TRUE(same_bits(resumed.variance, uninterrupted.variance)) << "resumed after pass " << k;
        EXPECT_EQ(resumed.weight, uninterrupted.weight);
        // The passes after the checkpoint report the noise the uninterrupted ones did (the normaliser is
        // restored, not recomputed from the resumed film).
        ASSERT_EQ(rest.noise.size(), full.noise.size() - k - 1);
        for (size_t p = 0; p < rest.noise.size(); ++p) {
            const double want = full.noise[k + 1 + p];
            if (std::isnan(want))
                EXPECT_TRUE(std::isnan(rest.noise[p]));
            else
                EXPECT_EQ(rest.noise[p], want) << "pass " << k + 1 + p;
        }
    }
}

// What a stopped render leaves: cancelled after a pass (here from on_pass, after the integrator's
// end_pass), the final state is that pass's; cancelled while the integrator learned from a pass (from
// end_pass), that pass is never checkpointed and the last checkpoint stays the one before it.
struct StoppedRender {
    RenderResult result;
    std::vector<int> checkpoints;  // spp_done of each checkpoint, the final one last (negated)
    std::optional<RenderState> final_state;
};

StoppedRender stop_after_8_spp(bool in_end_pass) {
    GaussianFilter filter;
    const FrameSetup setup{16, 8, &filter, false, 4, 3, false};
    std::atomic<bool> cancel{false};
    RenderOptions opt;
    opt.spp = 64;
    opt.cancel = &cancel;
    StoppedRender out;
    const auto stop = [&](int spp) {
        if (spp >= 8) cancel = true;
    };
    if (in_end_pass)
        opt.end_pass = [&](const PassReport& pass) { stop(pass.spp_done); };
    else
        opt.on_pass = [&](int spp, double, const Image&) { stop(spp); };
    opt.checkpoint = [&](const std::function<RenderState()>& state, bool final) {
        out.checkpoints.push_back(final ? -state().spp_done : state().spp_done);
        if (final) out.final_state = state();
    };
    out.result = render_frame(setup, signal, opt);
    return out;
}

TEST(Checkpoint, AStoppedRenderLeavesItsLastCompleteState) {
    const StoppedRender after = stop_after_8_spp(false);
    EXPECT_TRUE(after.result.stats.cancelled);
    EXPECT_EQ(after.result.spp, 8);
    EXPECT_EQ(after.checkpoints, std::vector<int>({1, 2, 4, 8, -8}));
    ASSERT_TRUE(after.final_state);
    EXPECT_EQ(after.final_state->passes, after.result.stats.passes);

    const StoppedRender during = stop_after_8_spp(true);
    EXPECT_EQ(during.result.spp, 8);
    EXPECT_EQ(during.checkpoints, std::vector<int>({1, 2, 4}));
    EXPECT_FALSE(during.final_state);

    // Resuming another sample range is refused.
    GaussianFilter filter;
    const FrameSetup setup{16, 8, &filter, false, 4, 3, false};
    RenderOptions other;
    other.spp = 64;
    other.first_sample = 1;
    other.resume = &*after.final_state;
    EXPECT_THROW(render_frame(setup, signal, other), std::invalid_argument);
}

}  // namespace
}  // namespace volguide
