// Shape sampling (oracles.md §8):
//  - pdf_direction integrates to one over the sphere of directions (Monte-Carlo z-test),
//  - every sample_direction sample reports the pdf that pdf_direction gives for it,
//  - chi-square tests of the sampled distributions in domains where the pdf is smooth (the
//    harness' quadrature cannot see silhouettes cutting through a histogram cell):
//      sphere seen from outside: (phi, cos theta) in the frame of the visible cone (uniform),
//      sphere seen from inside: directions on the whole sphere,
//      area sampling (sample_position): rectangle uv, disk (r^2, phi), cube faces weighted by area.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "support/chi2.h"
#include "support/test_support.h"
#include "unit/test_shape_util.h"
#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/geometry/accel.h"

using namespace volguide;
using namespace volguide::test;

namespace {

struct ShapeCase {
    std::string name;
    std::shared_ptr<Shape> shape;
    Point3f ref;
    bool all_hits;  // density of a direction = sum over every surface point along it (area sampling)
};

// pdf of sample_direction producing direction d: pdf_direction at the first hit, or summed over
// all hits along the ray when the shape may be crossed several times (area sampling).
double direction_pdf(const ShapeCase& c, const Accel& accel, const Vec3f& d) {
    Interaction ref;
    ref.p = c.ref;
    Ray ray(c.ref, d);
    double total = 0.0;
    for (int k = 0; k < 16; ++k) {
        SurfaceInteraction si;
        if (!accel.intersect(ray, si)) break;
        DirectionSample ds;
        ds.p = si.p;
        ds.n = si.n;
        ds.uv = si.uv;
        ds.d = d;
        ds.dist = norm(si.p - c.ref);
        total += c.shape->pdf_direction(ref, ds);
        if (!c.all_hits) break;
        ray = Ray(si.offset_origin(d), d);
    }
    return total;
}

std::shared_ptr<Shape> test_sphere() {
    return make_shape(ShapeProps("sphere").p("center", {0.2f, -0.1f, 0.3f}).f("radius", 0.7));
}

std::vector<ShapeCase> shape_cases() {
    std::vector<ShapeCase> out;
    auto sphere = test_sphere();
    out.push_back({"sphere_outside", sphere, {1.5f, 1.0f, 0.8f}, false});
    out.push_back({"sphere_far", sphere, {40.f, 30.f, -20.f}, false});  // small-cone Taylor branch
    out.push_back({"sphere_inside", sphere, {0.4f, 0.1f, 0.1f}, false});
    auto flipped = make_shape(ShapeProps("sphere").b("flip_normals", true).f("radius", 2));
    out.push_back({"sphere_flipped_inside", flipped, {0.5f, -0.3f, 0.9f}, false});
    out.push_back({"rectangle",
                   make_shape(ShapeProps("rectangle").t("to_world", Transform::rotate({1, 1, 0}, 30.f))),
                   {0.3f, 0.2f, 1.2f},
                   true});
    out.push_back({"disk",
                   make_shape(ShapeProps("disk").t("to_world", Transform::scale({1.5f, 0.5f, 1}))),
                   {0.1f, 0.8f, -0.6f},
                   true});
    out.push_back({"cube",
                   make_shape(ShapeProps("cube").t("to_world", Transform::rotate({0, 0, 1}, 20.f))),
                   {2.5f, 0.5f, 1.5f},
                   true});
    out.push_back({"cube_inside", make_shape(ShapeProps("cube")), {0.2f, -0.5f, 0.3f}, true});
    auto cylinder = make_shape(
        ShapeProps("cylinder").p("p0", {0.f, 0.f, -1.f}).p("p1", {0.3f, 0.2f, 1.f}).f("radius", 0.6));
    out.push_back({"cylinder", cylinder, {2.f, 0.5f, 0.3f}, true});
    out.push_back({"cylinder_inside", cylinder, {0.1f, 0.f, 0.f}, true});
    namespace fs = std::filesystem;
    fs::path torus =
        fs::path(shared_dir()) / "mitsuba-data/tests/scenes/participating_media/meshes/torus1.obj";
    if (fs::exists(torus))
        out.push_back({"torus_obj",
                       make_shape(ShapeProps("obj").s("filename", torus.string())),
                       {2.f, 1.5f, 1.f},
                       true});
    return out;
}

}  // namespace

TEST(ShapeSampling, PdfIntegratesToOne) {
    for (const ShapeCase& c : shape_cases()) {
        SCOPED_TRACE(c.name);
        Accel accel({c.shape.get()});
        const int n = 200000;
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < n; ++i) {
            Sampler s(7, 0, uint64_t(i));
            Vec3f d = warp::square_to_uniform_sphere(s.next_2d());
            double v = direction_pdf(c, accel, d) / InvFourPi;
            sum += v;
            sum2 += v * v;
        }
        double mean = sum / n, var = (sum2 / n - mean * mean) / (n - 1);
        double z = (mean - 1.0) / std::sqrt(var);
        // |z| < 4.4: two-sided error rate ~1e-5 per case.
        EXPECT_LT(std::abs(z), 4.4) << "integral " << mean << " +- " << std::sqrt(var);
    }
}

TEST(ShapeSampling, SamplePdfMatchesPdfDirection) {
    for (const ShapeCase& c : shape_cases()) {
        SCOPED_TRACE(c.name);
        Interaction ref;
        ref.p = c.ref;
        int mismatches = 0, invalid = 0;
        for (int i = 0; i < 20000; ++i) {
            Sampler s(11, 0, uint64_t(i));
            DirectionSample ds = c.shape->sample_direction(ref, s.next_2d());
            if (!(ds.pdf > 0.f)) {
                ++invalid;
                continue;
            }
            float pdf = c.shape->pdf_direction(ref, ds);
            if (std::abs(pdf - ds.pdf) > 1e-3f * ds.pdf) ++mismatches;
            if (std::abs(norm(ds.p - c.ref) - ds.dist) > 1e-4f * (1.f + ds.dist)) ++mismatches;
            if (std::abs(norm(ds.d) - 1.f) > 1e-5f) ++mismatches;
            if (std::abs(norm(ds.n) - 1.f) > 1e-5f) ++mismatches;
        }
        EXPECT_EQ(mismatches, 0);
        EXPECT_LT(invalid, 5);
    }
}

// Directions towards a sphere seen from outside, in the frame of the visible cone: uniform in
// (phi, cos theta) over [-pi, pi] x [cos theta_max, 1] with density pdf_direction.
TEST(ShapeSampling, SphereConeChi2) {
    auto sphere = test_sphere();
    const Point3f center(0.2f, -0.1f, 0.3f);
    const Point3f refs[] = {
        {1.5f, 1.0f, 0.8f}, {0.915f, -0.1f, 0.3f}, {40.f, 30.f, -20.f}};  // far, grazing, tiny cone
    for (const Point3f& rp : refs) {
        SCOPED_TRACE(::testing::Message() << "ref " << rp);
        Interaction ref;
        ref.p = rp;
        Vec3f axis_f = normalize(center - rp);
        Frame frame(axis_f);
        double dist = norm(Vec3d(center) - Vec3d(rp)), sin_max = std::min(1.0, 0.7 / dist);
        double cos_max = std::sqrt(1.0 - sin_max * sin_max);
        auto sample = [&](Sampler& s) {
            DirectionSample ds = sphere->sample_direction(ref, s.next_2d());
            Vec3f l = frame.to_local(ds.d);
            double cos_t = std::clamp(double(l.z), -1.0, 1.0);
            // y = 1 - cos theta (kept precise for narrow cones), x = phi.
            double sin2 = double(l.x) * l.x + double(l.y) * l.y;
            double one_minus_cos = sin2 / (1.0 + cos_t);
            return ChiSquareSample{Vec3f(float(std::atan2(l.y, l.x)), float(one_minus_cos), 0.f), Color3(1.f),
                                   ds.pdf > 0.f, false};
        };
        double pdf_value = double(sphere->pdf_direction(ref, DirectionSample{}));
        // The domain extends slightly past the cone (float rounding of the samples at its rim).
        const double y_max = sin_max * sin_max / (1.0 + cos_max);
        auto pdf = [&](const Vec3f& p) { return p.y <= y_max ? pdf_value : 0.0; };
        ChiSquareOptions opt;
        opt.sample_count = 200000;
        opt.rows = 20;
        opt.cols = 20;
        opt.test_count = 3;
        Rect2 dom{-Pi, 0.0, Pi, y_max * 1.001};
        ChiSquareResult r = chi2_test_plane(sample, pdf, dom, opt);
        EXPECT_TRUE(r.passed) << r.report;
        EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3);
    }
}

// Directions from inside a sphere: every direction hits, the pdf is smooth on the sphere.
TEST(ShapeSampling, SphereInsideChi2) {
    std::vector<ShapeCase> inside;
    for (const ShapeCase& c : shape_cases())
        if (c.name.find("inside") != std::string::npos && c.name.find("sphere") != std::string::npos)
            inside.push_back(c);
    ASSERT_EQ(inside.size(), 2u);
    for (const ShapeCase& c : inside) {
        SCOPED_TRACE(c.name);
        Accel accel({c.shape.get()});
        Interaction ref;
        ref.p = c.ref;
        ChiSquareOptions opt;
        opt.sample_count = 300000;
        opt.test_count = 2;
        auto sample = [&](Sampler& s) {
            DirectionSample ds = c.shape->sample_direction(ref, s.next_2d());
            return ChiSquareSample{ds.d, Color3(1.f), ds.pdf > 0.f, false};
        };
        auto pdf = [&](const Vec3f& d) { return direction_pdf(c, accel, d); };
        ChiSquareResult r = chi2_test_sphere(sample, pdf, opt);
        EXPECT_TRUE(r.passed) << r.report;
    }
}

// sample_position is uniform in area: rectangle uv uniform on [0,1]^2.
TEST(ShapeSampling, RectanglePositionChi2) {
    auto rect = make_shape(ShapeProps("rectangle").t("to_world", Transform::scale({3, 0.5f, 1})));
    ChiSquareOptions opt;
    opt.sample_count = 200000;
    opt.rows = opt.cols = 20;
    opt.test_count = 3;
    auto sample = [&](Sampler& s) {
        PositionSample ps = rect->sample_position(s.next_2d());
        Point3f local(ps.p.x / 3.f, ps.p.y / 0.5f, ps.p.z);
        return ChiSquareSample{Vec3f(0.5f * (local.x + 1.f), 0.5f * (local.y + 1.f), 0.f), Color3(1.f),
                               ps.pdf > 0.f, false};
    };
    ChiSquareResult r = chi2_test_plane(
        sample, [](const Vec3f&) { return 1.0; }, Rect2{}, opt);
    EXPECT_TRUE(r.passed) << r.report;
}

// Disk: uniform area <=> (r^2, phi / 2pi) uniform on [0,1]^2 (r, phi from the reported uv).
TEST(ShapeSampling, DiskPositionChi2) {
    auto disk = make_shape(ShapeProps("disk").t("to_world", Transform::scale({2, 1, 1})));
    ChiSquareOptions opt;
    opt.sample_count = 200000;
    opt.rows = opt.cols = 20;
    opt.test_count = 3;
    int uv_mismatch = 0;
    auto sample = [&](Sampler& s) {
        PositionSample ps = disk->sample_position(s.next_2d());
        float x = ps.p.x / 2.f, y = ps.p.y;
        float r = std::sqrt(x * x + y * y);
        if (std::abs(r - ps.uv.x) > 1e-5f) ++uv_mismatch;
        return ChiSquareSample{Vec3f(r * r, ps.uv.y, 0.f), Color3(1.f), ps.pdf > 0.f, false};
    };
    ChiSquareResult r = chi2_test_plane(
        sample, [](const Vec3f&) { return 1.0; }, Rect2{}, opt);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_EQ(uv_mismatch, 0);
}

// Cube with non-uniform scale: face chosen in proportion to its area, uv uniform on the face.
// Domain x = face index + u in [0, 6], y = v.
TEST(ShapeSampling, CubePositionChi2) {
    const Vec3f scale(1, 2, 3);
    auto cube = make_shape(ShapeProps("cube").t("to_world", Transform::scale(scale)));
    // Mitsuba's face order: -y, +y, +x, +z, -x, -z.
    const int axis_of[6] = {1, 1, 0, 2, 0, 2};
    double face_area[6], total = 0;
    for (int f = 0; f < 6; ++f) {
        int a = axis_of[f];
        face_area[f] = 4.0 * scale[(a + 1) % 3] * scale[(a + 2) % 3];
        total += face_area[f];
    }
    auto face_index = [&](const Vec3f& local) {
        const Vec3f n[6] = {{0, -1, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {-1, 0, 0}, {0, 0, -1}};
        for (int f = 0; f < 6; ++f)
            if (std::abs(dot(local, n[f]) - 1.f) < 1e-5f) return f;
        return -1;
    };
    ChiSquareOptions opt;
    opt.sample_count = 300000;
    opt.rows = 10;
    opt.cols = 60;
    opt.test_count = 3;
    auto sample = [&](Sampler& s) {
        PositionSample ps = cube->sample_position(s.next_2d());
        Vec3f local = ps.p / scale;
        int f = face_index(local);
        return ChiSquareSample{Vec3f(float(f) + ps.uv.x, ps.uv.y, 0.f), Color3(1.f), f >= 0 && ps.pdf > 0.f,
                               false};
    };
    auto pdf = [&](const Vec3f& p) {
        int f = std::clamp(int(std::floor(p.x)), 0, 5);
        return face_area[f] / total;
    };
    ChiSquareResult r = chi2_test_plane(sample, pdf, Rect2{0, 0, 6, 1}, opt);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(cube->surface_area(), total, 1e-3 * total);
}
