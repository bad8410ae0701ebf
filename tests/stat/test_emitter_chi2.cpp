// Chi-square tests (oracles.md §8) of emitter direction sampling against the emitters' own
// pdf_direction, with the weight checked against eval / pdf: envmap (synthetic and museum.exr,
// with and without to_world), constant, and the bilinear warp behind the envmap on the plane.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "support/chi2.h"
#include "support/emitter_test_util.h"
#include "support/test_support.h"
#include "volguide/core/transform.h"
#include "volguide/render/emitters/bilinear_warp.h"

using namespace volguide;
using namespace volguide::test;

namespace {

constexpr int TestCount = 6;  // tests in this file, for the Sidak correction

ChiSquareOptions emitter_options() {
    ChiSquareOptions opt;
    opt.test_count = TestCount;
    return opt;
}

// Samples directions from `ref` and checks them against pdf_direction and eval.
ChiSquareResult emitter_chi2(const Emitter& e, const Interaction& ref, ChiSquareOptions opt = emitter_options()) {
    auto sample = [&](Sampler& s) {
        auto [ds, w] = e.sample_direction(ref, s.next_2d());
        ChiSquareSample r{ds.d, w};
        r.valid = ds.pdf > 0.f;
        return r;
    };
    auto pdf = [&](const Vec3f& d) {
        DirectionSample ds;
        ds.d = d;
        ds.emitter = &e;
        return double(e.pdf_direction(ref, ds));
    };
    auto eval = [&](const Vec3f& d) { return e.eval(escaped_ray(d)); };
    return chi2_test_sphere(sample, pdf, opt, eval);
}

void print_summary(const ChiSquareResult& r) {
    std::printf("chi2 = %.1f, dof = %d, p = %.4f (alpha' = %.5f), pdf integral = %.6f\n", r.statistic, r.dof,
                r.p_value, r.alpha_corrected, r.pdf_integral);
}

std::shared_ptr<Emitter> make_envmap(const std::string& file, const Transform& to_world = {}) {
    EmitterBuilder b("envmap");
    b.set("filename", file);
    if (!to_world.is_identity()) b.set("to_world", to_world, "transform");
    auto e = b.build();
    e->set_scene_bounds(BBox3f({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
    return e;
}

}  // namespace

TEST(EmitterChi2, EnvmapSynthetic) {
    auto e = make_envmap(write_temp_exr("sky.exr", synthetic_sky()));
    auto r = emitter_chi2(*e, reference_point({0.1f, 0.2f, 0.3f}));
    print_summary(r);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3) << r.report;
    EXPECT_EQ(r.weight_mismatches, 0u) << r.report;
}

TEST(EmitterChi2, EnvmapSyntheticRotated) {
    const Transform rot = Transform::rotate({1.f, 0.5f, 0.f}, 60.f);
    auto e = make_envmap(write_temp_exr("sky_rot.exr", synthetic_sky()), rot);
    auto r = emitter_chi2(*e, reference_point({0.f, 0.f, 0.f}));
    print_summary(r);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-3) << r.report;
    EXPECT_EQ(r.weight_mismatches, 0u) << r.report;
}

TEST(EmitterChi2, EnvmapMuseum) {
    const std::string file = shared_dir() + "/mitsuba-data/common/textures/museum.exr";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "missing test data " << file;
    auto e = make_envmap(file);
    auto r = emitter_chi2(*e, reference_point({0.f, 0.f, 0.f}));
    print_summary(r);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3) << r.report;
    EXPECT_EQ(r.weight_mismatches, 0u) << r.report;
}

TEST(EmitterChi2, Constant) {
    auto e = EmitterBuilder("constant").set("radiance", Color3(2.f, 1.f, 0.5f), "rgb").build();
    e->set_scene_bounds(BBox3f({0.f, 0.f, 0.f}, {1.f, 1.f, 1.f}));
    auto r = emitter_chi2(*e, reference_point({0.5f, 0.5f, 0.5f}));
    print_summary(r);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4) << r.report;
    EXPECT_EQ(r.weight_mismatches, 0u) << r.report;
}

// The warp itself on [0,1]^2: a 5x4 vertex grid with zeros, a peak and a zero row.
TEST(EmitterChi2, BilinearWarpPlane) {
    std::vector<float> v = {0.f, 1.f, 2.f,  0.f, 0.5f,  //
                            3.f, 0.f, 8.f,  1.f, 0.5f,  //
                            0.f, 0.f, 0.f,  0.f, 0.f,   //
                            1.f, 1.f, 0.2f, 4.f, 0.f};
    const BilinearWarp2D warp(v, 5, 4);
    ChiSquareOptions opt = emitter_options();
    opt.rows = opt.cols = 24;
    auto r = chi2_test_plane(
        [&](Sampler& s) {
            auto [p, pdf] = warp.sample(s.next_2d());
            ChiSquareSample out{Vec3f(p.x, p.y, 0.f)};
            out.valid = pdf > 0.f;
            // The returned pdf must be the density of the point returned.
            if (std::abs(pdf - warp.pdf(p)) > 1e-3f * pdf) out.valid = false;
            return out;
        },
        [&](const Vec3f& p) {
            return double(warp.pdf({p.x, p.y}));
        },
        Rect2{0, 0, 1, 1}, opt);
    print_summary(r);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4) << r.report;
}

// The harness must notice an envmap whose pdf ignores the sin(theta) factor.
TEST(EmitterChi2, DetectsWrongEnvmapPdf) {
    auto e = make_envmap(write_temp_exr("sky_bad.exr", synthetic_sky()));
    const Interaction ref = reference_point({0.f, 0.f, 0.f});
    ChiSquareOptions opt = emitter_options();
    opt.sample_count = 200000;
    auto r = chi2_test_sphere(
        [&](Sampler& s) { return ChiSquareSample{e->sample_direction(ref, s.next_2d()).first.d}; },
        [&](const Vec3f& d) {
            DirectionSample ds;
            ds.d = d;
            const double sin_theta = std::sqrt(std::max(0.0, 1.0 - double(d.y) * d.y));
            return double(e->pdf_direction(ref, ds)) * sin_theta * (Pi / 2.0);  // wrong Jacobian
        },
        opt);
    EXPECT_FALSE(r.passed) << r.report;
}
