// Area emitter on a mock unit square: one-sidedness, weight == eval / pdf, and pdf_direction
// equal to the pdf of the sample.
#include <gtest/gtest.h>

#include "support/emitter_test_util.h"
#include "support/mock_square.h"
#include "volguide/core/sampler.h"

using namespace volguide;
using namespace volguide::test;

TEST(AreaEmitter, WeightAndPdfConsistency) {
    MockSquare square;
    square.attach(EmitterBuilder("area").set("radiance", Color3(3.f, 2.f, 1.f), "rgb").build());
    const Emitter& e = *square.emitter();
    EXPECT_EQ(e.flags(), uint32_t(emitter_flags::Surface));
    EXPECT_EQ(e.shape(), &square);
    const Interaction ref = reference_point({0.3f, -0.4f, 0.8f});
    Sampler s(5, 0, 0);
    for (int i = 0; i < 1000; ++i) {
        auto [ds, w] = e.sample_direction(ref, s.next_2d());
        ASSERT_GT(ds.pdf, 0.f);
        EXPECT_FALSE(ds.delta);
        EXPECT_EQ(ds.emitter, &e);
        EXPECT_NEAR(norm(ref.p + ds.d * ds.dist - ds.p), 0.f, 1e-5f);
        // Solid-angle pdf of uniform area sampling: dist^2 / (area cos).
        const float expected_pdf = ds.dist * ds.dist / std::abs(ds.d.z);
        EXPECT_NEAR(ds.pdf, expected_pdf, 1e-4f * expected_pdf);
        EXPECT_NEAR(e.pdf_direction(ref, ds), ds.pdf, 1e-5f * ds.pdf);
        const Color3 radiance = e.eval(square.hit(ds.p, ds.d));
        EXPECT_EQ(radiance, Color3(3.f, 2.f, 1.f));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(w[c], radiance[c] / ds.pdf, 1e-5f * radiance[c] / ds.pdf);
    }
}

TEST(AreaEmitter, OneSided) {
    MockSquare square;
    square.attach(EmitterBuilder("area").build());  // default radiance 1
    const Emitter& e = *square.emitter();
    // Seen from behind (z < 0): no emission, zero pdf.
    const Interaction behind = reference_point({0.5f, 0.5f, -1.f});
    auto [ds, w] = e.sample_direction(behind, {0.5f, 0.5f});
    EXPECT_EQ(w, Color3(0.f));
    EXPECT_EQ(e.pdf_direction(behind, ds), 0.f);
    EXPECT_EQ(e.eval(square.hit({0.5f, 0.5f, 0.f}, {0.f, 0.f, 1.f})), Color3(0.f));
    EXPECT_EQ(e.eval(square.hit({0.5f, 0.5f, 0.f}, {0.f, 0.f, -1.f})), Color3(1.f));
    // A flipped square emits towards -z.
    MockSquare flipped(true);
    flipped.attach(EmitterBuilder("area").build());
    EXPECT_GT(flipped.emitter()->sample_direction(behind, {0.5f, 0.5f}).second.r, 0.f);
}

TEST(AreaEmitter, RejectsBadParameters) {
    EXPECT_THROW(EmitterBuilder("area").set("radiance", Color3(-1.f), "rgb").build(), InputError);
    EXPECT_THROW(EmitterBuilder("area").set("to_world", Transform(), "transform").build(), InputError);
}
