// The `projector` emitter and the spot light's projection `texture` (issue 40), Mitsuba 3's
// semantics: sample_direction's value against the image mapping (a point of known local position
// sees the texel it projects to, with Mitsuba's pi scale / (z^2 cos) weight); emission sampling
// against sample_direction (the flux of sample_ray's photons through a small patch equals the
// patch's irradiance from sample_direction integrated over its area, z-test, as
// test_emitter_sample_ray.cpp does for the other emitters); and E[sample_ray weight] = power() for
// the constant image (exact) and a textured one (power by quadrature, a 1 % tolerance).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/emitter_test_util.h"
#include "support/running_stats.h"
#include "volguide/core/frame.h"
#include "volguide/core/sampler.h"
#include "volguide/core/transform.h"
#include "volguide/render/textures/textures.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// A w x h image whose texel (x, y) is (x + 1, y + 1, 1 + x + w y), nearest lookup, clamped.
std::shared_ptr<Texture> projector_test_image(int w, int h) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.at(x, y) = Color3(float(x + 1), float(y + 1), float(1 + x + w * y));
    return std::make_shared<BitmapTexture>(std::move(img), BitmapFilter::Nearest, BitmapWrap::Clamp, UvTransform{});
}

void projector_expect_mean_is_power(const Emitter& e, double rel_tol) {
    Sampler s(7, 0, 0);
    ColorStats st;
    for (int i = 0; i < 200000; ++i) st.add(e.sample_ray(s.next_2d(), s.next_2d()).weight);
    const Color3 p = e.power();
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(st.mean(c), p[c], 4.0 * st.se(c) + rel_tol * std::abs(p[c])) << e.to_string() << " channel " << c;
}

// Photon flux through a one-sided square patch (centre c, normal n towards the light, side 2h)
// against sample_direction's irradiance over it.
void projector_expect_reciprocity(const Emitter& e, const Point3f& c, const Vec3f& n_in, float h) {
    const Vec3f n = normalize(n_in);
    const Frame frame(n);
    Sampler s(11, 0, 0);
    ColorStats flux, irr;
    uint64_t hits = 0;
    for (int i = 0; i < 2000000; ++i) {
        const RaySample rs = e.sample_ray(s.next_2d(), s.next_2d());
        Color3 w(0.f);
        const float dn = dot(rs.ray.d, n);
        if (dn < 0.f) {
            const float t = dot(c - rs.ray.o, n) / dn;
            const Vec3f q = frame.to_local(rs.ray(t) - c);
            if (t > 0.f && std::abs(q.x) <= h && std::abs(q.y) <= h) w = rs.weight, ++hits;
        }
        flux.add(w);
    }
    for (int i = 0; i < 200000; ++i) {
        const Vec2f a = s.next_2d();
        const Point3f x = c + frame.to_world({(2.f * a.x - 1.f) * h, (2.f * a.y - 1.f) * h, 0.f});
        auto [ds, w] = e.sample_direction(reference_point(x), s.next_2d());
        irr.add(w * (std::max(0.f, dot(ds.d, n)) * 4.f * h * h));
    }
    std::printf("%s: %llu hits, flux %.5g +- %.2g, irradiance x area %.5g +- %.2g\n", e.to_string().c_str(),
                (unsigned long long)hits, flux.mean(2), flux.se(2), irr.mean(2), irr.se(2));
    EXPECT_GT(hits, 1000u);
    for (int ch = 0; ch < 3; ++ch) {
        const double se = std::sqrt(flux.se(ch) * flux.se(ch) + irr.se(ch) * irr.se(ch)) + 1e-6 * irr.mean(ch);
        EXPECT_LT(std::abs(flux.mean(ch) - irr.mean(ch)) / se, 4.0) << e.to_string() << " channel " << ch;
    }
}

const Transform kProjectorToWorld =
    Transform::translate({0.2f, -0.1f, 0.3f}) * Transform::rotate({1.f, 0.3f, 0.f}, 40.f);

}  // namespace

TEST(EmitterProjector, ImageMappingAndWeight) {
    // An 8 x 4 image (aspect 2), horizontal fov 90 degrees: tan(fov / 2) = 1.
    auto e = EmitterBuilder("projector")
                 .set("irradiance", ObjectPtr(projector_test_image(8, 4)), "texture")
                 .set("fov", 90.0, "float")
                 .set("scale", 2.0, "float")
                 .set("to_world", kProjectorToWorld, "transform")
                 .build();
    // Local (x, y, z) = (0.4, -0.55, 2): uv = (0.5 - 0.4 / 4, 0.5 + 2 * 0.55 / 4) = (0.4, 0.775):
    // texel (3, 3) = (4, 4, 28) (without the aspect in v it would be row 2, with x unflipped column 4).
    const Vec3f local(0.4f, -0.55f, 2.f);
    const Point3f p = kProjectorToWorld.apply_point(Point3f(local.x, local.y, local.z));
    auto [ds, w] = e->sample_direction(reference_point(p), {0.5f, 0.5f});
    EXPECT_TRUE(ds.delta);
    const float cos_theta = local.z / norm(local);
    const float expected = Pi * 2.f / (local.z * local.z * cos_theta);
    EXPECT_NEAR(w.r, 4.f * expected, 1e-4f * expected);
    EXPECT_NEAR(w.g, 4.f * expected, 1e-4f * expected);
    EXPECT_NEAR(w.b, 28.f * expected, 1e-4f * expected);
    // Outside the image (|uv.x| beyond 1) and behind the projector: nothing.
    EXPECT_TRUE(e->sample_direction(reference_point(kProjectorToWorld.apply_point(Point3f(2.5f, 0.f, 2.f))), {}).second.is_black());
    EXPECT_TRUE(e->sample_direction(reference_point(kProjectorToWorld.apply_point(Point3f(0.f, 0.f, -1.f))), {}).second.is_black());
}

TEST(EmitterProjector, EmissionMatchesSampleDirection) {
    auto constant = EmitterBuilder("projector")
                        .set("irradiance", Color3(1.f, 2.f, 3.f), "rgb")
                        .set("fov", 60.0, "float")
                        .set("to_world", kProjectorToWorld, "transform")
                        .build();
    projector_expect_mean_is_power(*constant, 1e-5);
    const Point3f origin = kProjectorToWorld.apply_point(Point3f(0.f));
    const Vec3f off_axis = normalize(kProjectorToWorld.apply_vector({0.3f, 0.2f, 1.f}));
    projector_expect_reciprocity(*constant, origin + off_axis * 1.5f, -off_axis + Vec3f(0.2f, 0.f, 0.f), 0.1f);

    auto textured = EmitterBuilder("projector")
                        .set("irradiance", ObjectPtr(projector_test_image(3, 2)), "texture")
                        .set("fov", 70.0, "float")
                        .set("fov_axis", std::string("y"), "string")
                        .set("to_world", kProjectorToWorld, "transform")
                        .build();
    projector_expect_mean_is_power(*textured, 1e-2);
    projector_expect_reciprocity(*textured, origin + off_axis * 1.5f, -off_axis, 0.15f);
}

TEST(EmitterSpotTexture, MappingAndEmissionMatchSampleDirection) {
    const float cutoff = 30.f;
    auto e = EmitterBuilder("spot")
                 .set("to_world", kProjectorToWorld, "transform")
                 .set("cutoff_angle", double(cutoff), "float")
                 .set("beam_width", 20.0, "float")
                 .set("intensity", Color3(2.f, 1.f, 0.5f), "rgb")
                 .set("texture", ObjectPtr(projector_test_image(10, 10)), "texture")
                 .build();
    // Local direction (x, y, 1) with x = 0.55 tan(cutoff), y = -0.25 tan(cutoff): uv (0.775, 0.375):
    // texel (7, 3) = (8, 4, 38); inside the beam (angle < 20 degrees).
    const float t = std::tan(deg_to_rad(cutoff));
    const Vec3f local(0.55f * t, -0.25f * t, 1.f);
    const Point3f p = kProjectorToWorld.apply_point(Point3f(local.x, local.y, local.z) * 2.f);
    auto [ds, w] = e->sample_direction(reference_point(p), {0.5f, 0.5f});
    const float inv_d2 = 1.f / (4.f * squared_norm(local));
    EXPECT_NEAR(w.r, 2.f * 8.f * inv_d2, 1e-4f);
    EXPECT_NEAR(w.g, 1.f * 4.f * inv_d2, 1e-4f);
    EXPECT_NEAR(w.b, 0.5f * 38.f * inv_d2, 1e-4f);
    projector_expect_mean_is_power(*e, 1e-2);
    const Point3f origin = kProjectorToWorld.apply_point(Point3f(0.f));
    const Vec3f d = normalize(kProjectorToWorld.apply_vector({0.15f, 0.1f, 1.f}));
    projector_expect_reciprocity(*e, origin + d, -d, 0.12f);
}

TEST(EmitterSpotTexture, ConstantTextureRefusedAtItsLine) {
    EXPECT_THROW(EmitterBuilder("spot").set("texture", Color3(1.f), "rgb").build(), InputError);
}
