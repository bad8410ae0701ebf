// Emission sampling (Emitter::sample_ray, power) for the photon pre-pass, for every emitter type:
//  (a) E[weight] = power() within 4 standard errors (2e5 samples);
//  (b) the photons' directions (and origins) follow the intended distributions (chi-square, and for
//      the spot light the cone edge and the falloff profile against sample_direction);
//  (c) reciprocity: the flux of photons crossing a small one-sided patch equals the patch's
//      irradiance integrated over its area through sample_direction (z-test).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/chi2.h"
#include "support/emitter_test_util.h"
#include "support/cli.h"
#include "support/mock_square.h"
#include "support/running_stats.h"
#include "volguide/core/frame.h"
#include "volguide/core/transform.h"
#include "volguide/render/emitters/emitter_common.h"
#include "volguide/render/emitters/spot_falloff.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"

using namespace volguide;
using namespace volguide::test;

namespace {

constexpr uint64_t MeanSamples = 200000;
constexpr int Chi2Tests = 10;  // chi-square tests in this file, for the Sidak correction
const BBox3f Bounds({-1.f, -1.f, -1.f}, {1.f, 2.f, 1.f});

ChiSquareOptions chi2_options() {
    ChiSquareOptions opt;
    opt.test_count = Chi2Tests;
    return opt;
}

void print(const char* what, const ChiSquareResult& r) {
    std::printf("%s: chi2 = %.1f, dof = %d, p = %.4f\n", what, r.statistic, r.dof, r.p_value);
}

// (a) The photons' mean weight is the emitter's power. Deterministic weights have zero standard
// error, hence the small relative floor.
void expect_mean_weight_is_power(const Emitter& e, uint64_t seed = 7) {
    Sampler s(seed, 0, 0);
    ColorStats st;
    for (uint64_t i = 0; i < MeanSamples; ++i) {
        const RaySample rs = e.sample_ray(s.next_2d(), s.next_2d());
        ASSERT_TRUE(rs.weight.is_finite());
        st.add(rs.weight);
    }
    const Color3 p = e.power();
    for (int c = 0; c < 3; ++c) {
        const double tol = 4.0 * st.se(c) + 1e-5 * std::abs(p[c]);
        EXPECT_NEAR(st.mean(c), p[c], tol) << e.to_string() << " channel " << c << ", se " << st.se(c);
    }
}

// (c) One-sided square patch (centre c, normal n facing the light, side 2h). Photon side: flux of
// the photons crossing it from the front. Light side: irradiance by sample_direction at uniform
// points of the patch, times its area (so both estimate the same integral exactly). `light_side`
// (default e) is the emitter whose sample_direction is used.
void expect_reciprocity(const Emitter& e, const Point3f& c, const Vec3f& n_in, float h,
                        const Emitter* light_side = nullptr, uint64_t photons = 2000000, uint64_t refs = 200000) {
    if (!light_side) light_side = &e;
    const Vec3f n = normalize(n_in);
    const Frame frame(n);
    const float area = 4.f * h * h;
    Sampler s(11, 0, 0);
    ColorStats flux, irr;
    uint64_t hits = 0;
    for (uint64_t i = 0; i < photons; ++i) {
        const RaySample rs = e.sample_ray(s.next_2d(), s.next_2d());
        Color3 w(0.f);
        const float dn = dot(rs.ray.d, n);
        if (dn < 0.f) {  // arrives at the front face
            const float t = dot(c - rs.ray.o, n) / dn;
            const Vec3f q = frame.to_local(rs.ray(t) - c);
            if (t > 0.f && std::abs(q.x) <= h && std::abs(q.y) <= h) w = rs.weight, ++hits;
        }
        flux.add(w);
    }
    for (uint64_t i = 0; i < refs; ++i) {
        const Vec2f a = s.next_2d();
        const Point3f x = c + frame.to_world({(2.f * a.x - 1.f) * h, (2.f * a.y - 1.f) * h, 0.f});
        auto [ds, w] = light_side->sample_direction(reference_point(x), s.next_2d());
        irr.add(w * (std::max(0.f, dot(ds.d, n)) * area));
    }
    std::printf("%s: %llu patch hits, flux %.5g +- %.2g, irradiance x area %.5g +- %.2g\n",
                e.to_string().c_str(), (unsigned long long)hits, flux.mean(0), flux.se(0), irr.mean(0), irr.se(0));
    EXPECT_GT(hits, 1000u);
    for (int ch = 0; ch < 3; ++ch) {
        const double se = std::sqrt(sqr(flux.se(ch)) + sqr(irr.se(ch))) + 1e-6 * std::abs(irr.mean(ch));
        EXPECT_LT(std::abs(flux.mean(ch) - irr.mean(ch)) / se, 4.0)
            << e.to_string() << " channel " << ch << ": flux " << flux.mean(ch) << ", irradiance x area "
            << irr.mean(ch);
    }
}

// Origins of photons from infinity: outside the scene's bounding sphere, through its disk
// perpendicular to their direction, and uniform on that disk (chi-square on (r^2, phi / 2 pi)).
void expect_disk_origins(const Emitter& e) {
    const BSphere bs = bounding_sphere(Bounds);
    const float radius = bs.radius;  // the emitter pads it by a relative ray epsilon
    Sampler s(3, 0, 0);
    for (int i = 0; i < 100000; ++i) {
        const RaySample rs = e.sample_ray(s.next_2d(), s.next_2d());
        if (rs.weight.is_black()) continue;
        const Vec3f oc = rs.ray.o - bs.center;
        ASSERT_GE(norm(oc), radius) << "photon starts inside the bounding sphere";
        const float along = dot(oc, rs.ray.d);
        ASSERT_LT(along, 0.f) << "photon starts past the sphere";
        ASSERT_LE(norm(oc - rs.ray.d * along), radius * (1.f + 1e-4f)) << "photon misses the sphere's disk";
    }
    auto r = chi2_test_plane(
        [&](Sampler& smp) {
            const RaySample rs = e.sample_ray(smp.next_2d(), smp.next_2d());
            const Frame f(rs.ray.d);
            const Vec3f q = f.to_local(rs.ray.o - bs.center) / (bs.radius * (1.f + MitsubaRayEpsilon));
            const float phi = std::atan2(q.y, q.x);
            // atan2 may return exactly pi: keep the coordinates inside the unit square
            return ChiSquareSample{Vec3f(std::min(q.x * q.x + q.y * q.y, OneMinusEpsilon),
                                         std::min(phi * InvTwoPi + 0.5f, OneMinusEpsilon), 0.f)};
        },
        [](const Vec3f&) { return 1.0; }, Rect2{0, 0, 1, 1}, chi2_options());
    print("disk origins", r);
    EXPECT_TRUE(r.passed) << r.report;
}

}  // namespace

// ---- area ------------------------------------------------------------------------------------

// Unit square emitting (1, 2, 3) on its front side (+z, or -z when flipped): power pi L A; cosine
// directions on the side eval() emits to; origins uniform on the square.
TEST(EmitterSampleRay, Area) {
    for (bool flipped : {false, true}) {
        MockSquare square(flipped);
        square.attach(EmitterBuilder("area").set("radiance", Color3(1.f, 2.f, 3.f), "rgb").build());
        const Emitter& e = *square.emitter();
        const float side = flipped ? -1.f : 1.f;
        EXPECT_NEAR(e.power().g, 2.f * Pi, 1e-5f);
        expect_mean_weight_is_power(e);

        auto r = chi2_test_sphere(
            [&](Sampler& s) {
                const RaySample rs = e.sample_ray(s.next_2d(), s.next_2d());
                ChiSquareSample out{rs.ray.d, rs.weight};
                out.valid = !rs.weight.is_black();
                EXPECT_EQ(rs.n.z, side);
                return out;
            },
            [&](const Vec3f& d) { return std::max(0.0, double(side * d.z)) * InvPi; }, chi2_options(),
            // weight * pdf_dir = L cos / pdf_pos, with L as eval() sees it from d (pdf_pos = 1)
            [&](const Vec3f& d) { return e.eval(square.hit(Point3f(0.5f, 0.5f, 0.f), -d)) * std::abs(d.z); });
        print(flipped ? "area (flipped) directions" : "area directions", r);
        EXPECT_TRUE(r.passed) << r.report;
        EXPECT_EQ(r.weight_mismatches, 0u) << r.report;

        expect_reciprocity(e, {0.3f, 0.6f, side * 0.8f}, {0.2f, -0.1f, -side}, 0.15f);
    }
    MockSquare square;
    square.attach(EmitterBuilder("area").build());
    auto r = chi2_test_plane(
        [&](Sampler& s) {
            const RaySample rs = square.emitter()->sample_ray(s.next_2d(), s.next_2d());
            return ChiSquareSample{rs.ray.o};
        },
        [](const Vec3f&) { return 1.0; }, Rect2{0, 0, 1, 1}, chi2_options());
    print("area origins", r);
    EXPECT_TRUE(r.passed) << r.report;
}

// Textured radiance (checkerboard in uv): power is the stratified estimate of pi int L dA.
TEST(EmitterSampleRay, AreaTextured) {
    Properties tex("texture", "checkerboard", SourceLocation{"test.xml", 1});
    tex.set("color0", "param", Color3(4.f, 1.f, 0.f), SourceLocation{"test.xml", 2});
    tex.set("color1", "param", Color3(0.f, 1.f, 2.f), SourceLocation{"test.xml", 3});
    MockSquare square;
    square.attach(EmitterBuilder("area").set("radiance", create_texture(tex), "texture").build());
    const Emitter& e = *square.emitter();
    EXPECT_NEAR(e.power().r, Pi * 2.f, 1e-4f);  // pi x area-average of the checkerboard
    EXPECT_NEAR(e.power().b, Pi * 1.f, 1e-4f);
    expect_mean_weight_is_power(e);
    expect_reciprocity(e, {0.7f, 0.3f, 0.5f}, {0.f, 0.f, -1.f}, 0.1f);
}

// ---- point -----------------------------------------------------------------------------------

TEST(EmitterSampleRay, Point) {
    const Point3f pos(0.1f, 0.2f, 0.3f);
    auto e = EmitterBuilder("point").set("position", Vec3f(pos)).set("intensity", Color3(1.f, 2.f, 3.f), "rgb").build();
    EXPECT_NEAR(e->power().b, 12.f * Pi, 1e-4f);
    expect_mean_weight_is_power(*e);
    auto r = chi2_test_sphere(
        [&](Sampler& s) {
            const RaySample rs = e->sample_ray(s.next_2d(), s.next_2d());
            EXPECT_EQ(rs.ray.o, pos);
            return ChiSquareSample{rs.ray.d, rs.weight};
        },
        [](const Vec3f&) { return double(InvFourPi); }, chi2_options(),
        [](const Vec3f&) { return Color3(1.f, 2.f, 3.f); });  // weight x pdf = intensity
    print("point directions", r);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_EQ(r.weight_mismatches, 0u) << r.report;
    expect_reciprocity(*e, pos + Vec3f(0.3f, 0.f, 1.f), {-0.5f, 0.2f, -1.f}, 0.2f);
}

// ---- spot ------------------------------------------------------------------------------------

TEST(EmitterSampleRay, Spot) {
    const float cutoff = 30.f, beam = 20.f;
    const Transform to_world = Transform::translate({0.2f, -0.1f, 0.3f}) * Transform::rotate({1.f, 0.3f, 0.f}, 40.f);
    auto e = EmitterBuilder("spot")
                 .set("to_world", to_world, "transform")
                 .set("cutoff_angle", double(cutoff))
                 .set("beam_width", double(beam))
                 .set("intensity", Color3(2.f, 1.f, 0.5f), "rgb")
                 .build();
    const Point3f pos = to_world.apply_point(Point3f(0.f));
    const Transform to_local = to_world.inverse();
    auto local_dir = [&](const Vec3f& d) { return normalize(to_local.apply_vector(d)); };
    auto world_dir = [&](const Vec3f& l) { return normalize(to_world.apply_vector(l)); };
    expect_mean_weight_is_power(*e);
    // Power against a direct quadrature of the falloff (as sample_direction applies it) on the cone.
    auto intensity = [&](float theta, float phi) {  // seen through sample_direction at distance 2
        const Vec3f l(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
        return e->sample_direction(reference_point(pos + world_dir(l) * 2.f), {0.5f, 0.5f}).second * 4.f;
    };
    auto cone_integral = [&](double t0, double t1) {  // int I sin(theta) dtheta dphi over [t0, t1]
        const int steps = 400;
        double sum = 0.0;
        for (int i = 0; i < steps; ++i) {
            const double t = t0 + (i + 0.5) * (t1 - t0) / steps;
            sum += intensity(float(t), 0.7f).g * std::sin(t);
        }
        return sum * (t1 - t0) / steps * 2.0 * Pi;
    };
    EXPECT_NEAR(e->power().g, cone_integral(0.0, deg_to_rad(cutoff) * 1.05), 2e-4);

    // Directions: uniform in the cutoff cone (the grid zooms onto it).
    ChiSquareOptions opt = chi2_options();
    opt.min_cos_theta = std::cos(deg_to_rad(cutoff));
    auto r = chi2_test_sphere(
        [&](Sampler& s) {
            const RaySample rs = e->sample_ray(s.next_2d(), s.next_2d());
            return ChiSquareSample{local_dir(rs.ray.d), rs.weight};
        },
        [&](const Vec3f& d) { return d.z >= opt.min_cos_theta ? 1.0 / (2.0 * Pi * (1.0 - opt.min_cos_theta)) : 0.0; },
        opt);
    print("spot directions", r);
    EXPECT_TRUE(r.passed) << r.report;

    // Falloff profile and cone edge: radiant intensity of the photons per theta bin against the
    // bin average of sample_direction's intensity; nothing beyond the cutoff.
    const int bins = 24;
    const double theta_max = deg_to_rad(cutoff) * 1.1;
    std::vector<double> sum(bins, 0.0), sum2(bins, 0.0);
    const uint64_t n = 1000000;
    Sampler s(5, 0, 0);
    for (uint64_t i = 0; i < n; ++i) {
        const RaySample rs = e->sample_ray(s.next_2d(), s.next_2d());
        const double theta = std::acos(std::clamp(double(local_dir(rs.ray.d).z), -1.0, 1.0));
        ASSERT_LE(theta, deg_to_rad(cutoff) + 1e-3) << "photon outside the cone";
        const int b = std::min(bins - 1, int(theta / theta_max * bins));
        sum[b] += rs.weight.g;
        sum2[b] += sqr(double(rs.weight.g));
    }
    for (int b = 0; b < bins; ++b) {
        const double t0 = theta_max * b / bins, t1 = theta_max * (b + 1) / bins;
        const double d_omega = 2.0 * Pi * (std::cos(t0) - std::cos(t1));
        const double est = sum[b] / n / d_omega;
        const double se = std::sqrt(std::max(0.0, sum2[b] / n - sqr(sum[b] / n)) / n) / d_omega;
        const double ref = cone_integral(t0, t1) / d_omega;
        EXPECT_LE(std::abs(est - ref), 4.0 * se + 1e-3 * ref + 1e-7)
            << "bin " << b << " (theta " << rad_to_deg(t0) << ".." << rad_to_deg(t1) << "): photons " << est
            << " +- " << se << ", sample_direction " << ref;
    }
    // A patch straddling the ramp (25 degrees off the axis).
    const Vec3f d25 = world_dir({std::sin(deg_to_rad(25.f)), 0.f, std::cos(deg_to_rad(25.f))});
    expect_reciprocity(*e, pos + d25, -d25, 0.1f);
}

// ---- directional -----------------------------------------------------------------------------

TEST(EmitterSampleRay, Directional) {
    const Vec3f dir = normalize(Vec3f(0.3f, -1.f, 0.2f));
    auto e = EmitterBuilder("directional").set("direction", Vec3f(0.3f, -1.f, 0.2f))
                 .set("irradiance", Color3(1.f, 2.f, 3.f), "rgb").build();
    e->set_scene_bounds(Bounds);
    const float r2 = sqr(bounding_sphere(Bounds).radius);
    EXPECT_NEAR(e->power().r, Pi * r2, 1e-3f * Pi * r2);
    expect_mean_weight_is_power(*e);
    Sampler s(9, 0, 0);
    for (int i = 0; i < 1000; ++i) EXPECT_LT(norm(e->sample_ray(s.next_2d(), s.next_2d()).ray.d - dir), 1e-6f);
    expect_disk_origins(*e);
    expect_reciprocity(*e, {0.2f, 0.5f, 0.1f}, -dir + Vec3f(0.3f, 0.f, 0.2f), 0.3f);
}

// ---- constant --------------------------------------------------------------------------------

TEST(EmitterSampleRay, Constant) {
    auto e = EmitterBuilder("constant").set("radiance", Color3(1.f, 2.f, 3.f), "rgb").build();
    e->set_scene_bounds(Bounds);
    const float disk = Pi * sqr(bounding_sphere(Bounds).radius * (1.f + MitsubaRayEpsilon));
    EXPECT_NEAR(e->power().r, 4.f * Pi * disk, 1e-4f * disk);
    expect_mean_weight_is_power(*e);
    // Directions towards the light (against the photon's travel) uniform on the sphere.
    auto r = chi2_test_sphere(
        [&](Sampler& s) {
            const RaySample rs = e->sample_ray(s.next_2d(), s.next_2d());
            return ChiSquareSample{-rs.ray.d, rs.weight};
        },
        [](const Vec3f&) { return double(InvFourPi); }, chi2_options(),
        [&](const Vec3f& d) { return e->eval(escaped_ray(d)) * disk; });
    print("constant directions", r);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_EQ(r.weight_mismatches, 0u) << r.report;
    expect_disk_origins(*e);
    expect_reciprocity(*e, {0.f, 0.5f, 0.f}, {0.3f, 1.f, 0.2f}, 0.25f);
}

// ---- envmap ----------------------------------------------------------------------------------

namespace {
const Transform SkyRotation = Transform::rotate({1.f, 0.5f, 0.f}, 60.f);

std::shared_ptr<Emitter> make_sky(const std::string& name, bool mis_compensation) {
    EmitterBuilder b("envmap");
    b.set("filename", write_temp_exr(name, synthetic_sky())).set("to_world", SkyRotation, "transform");
    if (mis_compensation) b.set("mis_compensation", true);
    auto e = b.build();
    e->set_scene_bounds(Bounds);
    return e;
}
}  // namespace

TEST(EmitterSampleRay, Envmap) {
    auto e = make_sky("sky.exr", false);
    const float disk = Pi * sqr(bounding_sphere(Bounds).radius * (1.f + MitsubaRayEpsilon));
    // power / disk = integral of the radiance over the sphere: check the closed form by quadrature.
    Color3 quad(0.f);
    const int nt = 600, np = 1200;
    for (int j = 0; j < nt; ++j)
        for (int i = 0; i < np; ++i) {
            const float theta = (j + 0.5f) * Pi / nt, phi = (i + 0.5f) * 2.f * Pi / np;
            const Vec3f d = normalize(SkyRotation.apply_vector(envmap_direction(phi * InvTwoPi, theta * InvPi)));
            quad += e->eval(escaped_ray(d)) * (std::sin(theta) * (Pi / nt) * (2.f * Pi / np));
        }
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(e->power()[c] / disk, quad[c], 2e-3 * quad[c]) << "channel " << c;
    expect_mean_weight_is_power(*e);

    // Photons arrive from directions distributed as the map's own pdf_direction.
    auto r = chi2_test_sphere(
        [&](Sampler& s) {
            const RaySample rs = e->sample_ray(s.next_2d(), s.next_2d());
            ChiSquareSample out{-rs.ray.d, rs.weight};
            out.valid = !rs.weight.is_black();
            return out;
        },
        [&](const Vec3f& d) {
            DirectionSample ds;
            ds.d = d;
            ds.emitter = e.get();
            return double(e->pdf_direction(reference_point(Point3f(0.f)), ds));
        },
        chi2_options(), [&](const Vec3f& d) { return e->eval(escaped_ray(d)) * disk; });
    print("envmap directions", r);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_EQ(r.weight_mismatches, 0u) << r.report;
    expect_disk_origins(*e);
    const Vec3f sun = normalize(SkyRotation.apply_vector(envmap_direction(5.5f / 24.f, 3.f / 11.f)));
    expect_reciprocity(*e, {0.1f, 0.4f, -0.2f}, sun + Vec3f(0.2f, 0.f, 0.f), 0.25f);
    expect_reciprocity(*e, {0.1f, 0.4f, -0.2f}, Vec3f(0.f, -1.f, 0.f), 0.25f);
}

// MIS compensation changes sample_direction's pdf (it leaves dim regions to BSDF sampling, so its
// irradiance alone is biased), not the photons: compare them with the uncompensated map.
TEST(EmitterSampleRay, EnvmapMisCompensation) {
    auto e = make_sky("sky_mis.exr", true);
    auto plain = make_sky("sky_plain.exr", false);
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(e->power()[c], plain->power()[c]);
    expect_mean_weight_is_power(*e);
    expect_reciprocity(*e, {0.1f, 0.4f, -0.2f}, Vec3f(0.f, 1.f, 0.3f), 0.25f, plain.get());
}

// ---- scene: emitter choice by power ----------------------------------------------------------

TEST(EmitterSampleRay, SceneChoosesEmittersByPower) {
    TempDir dir("emission-choice");
    const std::string path = dir.write("scene.xml", R"(<scene version="3.0.0">
    <sensor type="perspective">
        <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film>
    </sensor>
    <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter></shape>
    <shape type="sphere"><point name="center" x="0" y="0" z="-3"/><float name="radius" value="0.5"/></shape>
    <emitter type="point"><point name="position" x="0" y="0" z="2"/><rgb name="intensity" value="0.5"/></emitter>
    <emitter type="directional"><vector name="direction" x="0" y="0" z="-1"/><rgb name="irradiance" value="0.1"/></emitter>
    <emitter type="constant"><rgb name="radiance" value="0"/></emitter>
</scene>)");
    const auto scene = load_scene(path);
    const auto& emitters = scene->emitters();
    ASSERT_EQ(emitters.size(), 4u);
    double total = 0.0;
    for (const auto& e : emitters) total += e->power().average();
    std::vector<double> expected;
    for (const auto& e : emitters) {
        expected.push_back(e->power().average() / total);
        EXPECT_NEAR(scene->emission_probability(e.get()), expected.back(), 1e-6);
    }
    EXPECT_EQ(expected.back(), 0.0);  // the black environment is never chosen
    std::vector<uint64_t> counts(emitters.size(), 0);
    Sampler s(13, 0, 0);
    for (int i = 0; i < 200000; ++i) {
        auto [e, prob] = scene->sample_emitter_for_emission(s.next_1d());
        ASSERT_NE(e, nullptr);
        EXPECT_FLOAT_EQ(prob, scene->emission_probability(e));
        for (size_t k = 0; k < emitters.size(); ++k) counts[k] += emitters[k].get() == e;
    }
    EXPECT_EQ(counts.back(), 0u);
    auto r = chi2_test_discrete(counts, expected);
    EXPECT_TRUE(r.passed) << r.report;
}
