// Chi-square test of the area emitter's direction sampling on a mock unit square. The sampled
// directions are traced to the square and binned there (on the sphere of directions the pdf jumps
// to zero at the square's silhouette, which defeats the cell quadrature); the density tested is
// the emitter's pdf_direction converted to area, pdf * |cos| / dist^2, so the test checks the
// directions, the solid-angle pdf and the weights together.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/chi2.h"
#include "support/emitter_test_util.h"
#include "support/mock_square.h"

using namespace volguide;
using namespace volguide::test;

TEST(EmitterChi2, AreaSquare) {
    MockSquare square;
    square.attach(EmitterBuilder("area").set("radiance", Color3(1.f, 2.f, 3.f), "rgb").build());
    const Emitter& e = *square.emitter();
    const Interaction ref = reference_point({0.2f, 0.7f, 0.6f});

    // The record an integrator builds for the emitter point q seen from ref.
    auto record = [&](const Point3f& q) {
        DirectionSample ds;
        ds.p = q;
        ds.n = Normal3f(0.f, 0.f, 1.f);
        ds.dist = norm(q - ref.p);
        ds.d = (q - ref.p) / ds.dist;
        ds.uv = Vec2f(q.x, q.y);
        ds.emitter = &e;
        return ds;
    };
    // Solid angle to area at q.
    auto jacobian = [&](const DirectionSample& ds) { return std::abs(ds.d.z) / (ds.dist * ds.dist); };

    ChiSquareOptions opt;
    opt.rows = opt.cols = 40;
    auto r = chi2_test_plane(
        [&](Sampler& s) {
            auto [ds, w] = e.sample_direction(ref, s.next_2d());
            ChiSquareSample out{Vec3f(0.f), w};
            float t;
            out.valid = ds.pdf > 0.f && square.intersect_square(ref.p, ds.d, t);
            if (out.valid) out.d = ref.p + ds.d * t;
            return out;
        },
        [&](const Vec3f& q) {
            const DirectionSample ds = record({q.x, q.y, 0.f});
            return double(e.pdf_direction(ref, ds)) * jacobian(ds);
        },
        Rect2{0, 0, 1, 1}, opt,
        [&](const Vec3f& q) {
            const DirectionSample ds = record({q.x, q.y, 0.f});
            return e.eval(square.hit(ds.p, ds.d)) * jacobian(ds);
        });
    std::printf("chi2 = %.1f, dof = %d, p = %.4f, pdf integral = %.6f\n", r.statistic, r.dof, r.p_value,
                r.pdf_integral);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4) << r.report;
    EXPECT_EQ(r.rest_observed, 0u) << r.report;
    EXPECT_EQ(r.weight_mismatches, 0u) << r.report;
}
