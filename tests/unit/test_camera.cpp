// Perspective and orthographic cameras: Mitsuba's fov rules, the analytic pinhole projection,
// handedness (camera +x is image left), near/far clipping, orthographic extents, parameter errors.
#include <gtest/gtest.h>

#include <cmath>

#include "volguide/core/log.h"
#include "volguide/core/properties.h"
#include "volguide/render/sensors/hdrfilm.h"
#include "volguide/render/sensors/orthographic.h"
#include "volguide/render/sensors/perspective.h"
#include "volguide/render/sensors/rfilters.h"
#include "volguide/render/sensors/sampler_settings.h"
#include "volguide/scene/factories.h"

namespace volguide {
namespace {

const SourceLocation kCameraLoc{"camera_test.xml", 7};
constexpr double kPi = 3.14159265358979323846;
double rad(double deg) {
    return deg * kPi / 180.0;
}

std::shared_ptr<Film> film(int w, int h) {
    return std::make_shared<Film>(w, h, std::make_shared<BoxFilter>());
}

Properties sensor_props(const std::string& type, int w, int h) {
    Properties p("sensor", type, kCameraLoc);
    p.set("", "film", film(w, h), kCameraLoc);
    return p;
}

// Projects a camera-space point to film uv with an independent pinhole model: image x grows toward
// camera -x, image y toward camera -y, square pixels, horizontal half-width tan(fov_x / 2).
Point2f project(const Vec3f& p, double x_fov_deg, int w, int h) {
    double t = std::tan(rad(x_fov_deg) / 2), aspect = double(w) / h;
    double sx = p.x / p.z / t, sy = p.y / p.z / t * aspect;  // in [-1, 1] inside the frame
    return {float(0.5 - 0.5 * sx), float(0.5 - 0.5 * sy)};
}

TEST(Camera, CentreRayLooksDownPlusZFromTheNearPlane) {
    PerspectiveCamera cam(film(64, 48), Transform(), 60.f, 0.5f, 100.f);
    auto [ray, w] = cam.sample_ray({0.5f, 0.5f}, {0.5f, 0.5f});
    EXPECT_NEAR(ray.d.x, 0.f, 1e-6f);
    EXPECT_NEAR(ray.d.y, 0.f, 1e-6f);
    EXPECT_NEAR(ray.d.z, 1.f, 1e-6f);
    EXPECT_NEAR(ray.o.z, 0.5f, 1e-6f);
    EXPECT_NEAR(ray.tmax, 99.5f, 1e-4f);
    EXPECT_EQ(w, Color3(1.f));
}

TEST(Camera, PixelRaysMatchTheAnalyticPinhole) {
    const int W = 40, H = 30;
    const float fov = 52.f;
    PerspectiveCamera cam(film(W, H), Transform(), fov, 0.1f, 50.f);
    for (int j = 0; j < H; j += 7)
        for (int i = 0; i < W; i += 5) {
            Point2f uv((i + 0.25f) / W, (j + 0.75f) / H);
            auto [ray, w] = cam.sample_ray(uv, {0.5f, 0.5f});
            EXPECT_NEAR(norm(ray.d), 1.f, 1e-6f);
            // The origin lies on the near plane, on the line through the pinhole.
            EXPECT_NEAR(ray.o.z, 0.1f, 1e-6f);
            EXPECT_NEAR(norm(cross(ray.o, ray.d)), 0.f, 1e-6f);
            // The far end lies on the far plane.
            EXPECT_NEAR(ray(ray.tmax).z, 50.f, 1e-3f);
            Point2f back = project(ray(3.f), fov, W, H);
            EXPECT_NEAR(back.x, uv.x, 1e-5f);
            EXPECT_NEAR(back.y, uv.y, 1e-5f);
        }
}

TEST(Camera, CameraPlusXAppearsOnTheLeft) {
    // Mitsuba: camera +x is left, +y is up.
    PerspectiveCamera cam(film(32, 32), Transform(), 40.f);
    EXPECT_GT(cam.sample_ray({0.1f, 0.5f}, {}).first.d.x, 0.f);
    EXPECT_LT(cam.sample_ray({0.9f, 0.5f}, {}).first.d.x, 0.f);
    EXPECT_GT(cam.sample_ray({0.5f, 0.1f}, {}).first.d.y, 0.f);
    EXPECT_LT(cam.sample_ray({0.5f, 0.9f}, {}).first.d.y, 0.f);
    // A point at camera-space +x projects onto the left half.
    EXPECT_LT(project(Vec3f(1.f, 0.f, 5.f), 40.f, 32, 32).x, 0.5f);

    // With <lookat origin="0,0,5" target="0,0,0" up="0,1,0">, world -x is on the left (not mirrored).
    Transform look = Transform::look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
    PerspectiveCamera world_cam(film(32, 32), look, 40.f);
    auto [left_ray, lw] = world_cam.sample_ray({0.2f, 0.5f}, {});
    EXPECT_LT(left_ray.d.x, 0.f);
    EXPECT_LT(left_ray.d.z, 0.f);
    auto [up_ray, uw] = world_cam.sample_ray({0.5f, 0.2f}, {});
    EXPECT_GT(up_ray.d.y, 0.f);
}

// Half-angle of the field of view along the requested axis, read back from edge rays.
struct FovCase {
    const char* axis;
    int w, h;
    char measured;  // 'x', 'y' or 'd' (diagonal)
};

TEST(Camera, FovAxisFollowsMitsuba) {
    const FovCase cases[] = {{"x", 64, 48, 'x'},       {"y", 64, 48, 'y'},      {"diagonal", 64, 48, 'd'},
                             {"smaller", 64, 48, 'y'}, {"larger", 64, 48, 'x'}, {"smaller", 30, 50, 'x'},
                             {"larger", 30, 50, 'y'},  {"y", 30, 50, 'y'},      {"diagonal", 30, 50, 'd'}};
    for (const auto& c : cases) {
        SCOPED_TRACE(std::string(c.axis) + " " + std::to_string(c.w) + "x" + std::to_string(c.h));
        const float fov = 47.f;
        Properties p = sensor_props("perspective", c.w, c.h);
        p.set("fov", "float", 47.0, kCameraLoc);
        p.set("fov_axis", "string", std::string(c.axis), kCameraLoc);
        auto cam = std::dynamic_pointer_cast<PerspectiveCamera>(create_sensor(p));
        ASSERT_TRUE(cam);
        p.check_all_used();
        Point2f edge = c.measured == 'x'   ? Point2f(0.f, 0.5f)
                       : c.measured == 'y' ? Point2f(0.5f, 0.f)
                                           : Point2f(0.f, 0.f);
        Vec3f d = cam->sample_ray(edge, {}).first.d;
        double off_axis = std::sqrt(double(d.x) * d.x + double(d.y) * d.y);
        EXPECT_NEAR(std::atan2(off_axis, double(d.z)), rad(fov) / 2, 1e-5);
    }
}

TEST(Camera, HorizontalFovConversions) {
    EXPECT_DOUBLE_EQ(horizontal_fov(40, "x", 2.0), 40);
    // Vertical 90 degrees on a 2:1 film: tan(x/2) = 2 tan(45 deg).
    EXPECT_NEAR(horizontal_fov(90, "y", 2.0), 2 * std::atan(2.0) * 180 / kPi, 1e-9);
    EXPECT_NEAR(horizontal_fov(90, "smaller", 2.0), horizontal_fov(90, "y", 2.0), 1e-12);
    EXPECT_NEAR(horizontal_fov(90, "larger", 0.5), horizontal_fov(90, "y", 0.5), 1e-12);
    EXPECT_THROW(horizontal_fov(45, "z", 1.0), std::invalid_argument);
    // 50 mm on 35 mm film: diagonal 43.27 mm.
    EXPECT_NEAR(focal_length_to_diagonal_fov("50mm"),
                2 * std::atan(std::sqrt(36.0 * 36 + 24 * 24) / 100) * 180 / kPi, 1e-9);
    EXPECT_LT(focal_length_to_diagonal_fov("fifty"), 0);
}

TEST(Camera, FocalLengthIsADiagonalFov) {
    Properties p = sensor_props("perspective", 60, 40);
    p.set("focal_length", "string", std::string("35mm"), kCameraLoc);
    auto cam = std::dynamic_pointer_cast<PerspectiveCamera>(create_sensor(p));
    EXPECT_NEAR(cam->x_fov(), horizontal_fov(focal_length_to_diagonal_fov("35mm"), "diagonal", 1.5), 1e-4);
    // Default: 50mm.
    Properties q = sensor_props("perspective", 60, 40);
    auto def = std::dynamic_pointer_cast<PerspectiveCamera>(create_sensor(q));
    EXPECT_NEAR(def->x_fov(), horizontal_fov(focal_length_to_diagonal_fov("50mm"), "diagonal", 1.5), 1e-4);
}

TEST(Camera, ReadsClipPlanesFilmAndSampler) {
    Properties p = sensor_props("perspective", 20, 10);
    p.set("fov", "float", 30.0, kCameraLoc);
    p.set("near_clip", "float", 1.0, kCameraLoc);
    p.set("far_clip", "float", 1000.0, kCameraLoc);
    Properties sp("sampler", "independent", kCameraLoc);
    sp.set("sample_count", "integer", int64_t(64), kCameraLoc);
    sp.set("seed", "integer", int64_t(9), kCameraLoc);
    p.set("", "sampler", create_sampler(sp), kCameraLoc);
    sp.check_all_used();
    auto sensor = std::dynamic_pointer_cast<Sensor>(create_sensor(p));
    p.check_all_used();
    EXPECT_EQ(sensor->sample_count(), 64);
    EXPECT_EQ(sensor->seed(), 9u);
    EXPECT_EQ(sensor->film().width(), 20);
    auto [ray, w] = sensor->sample_ray({0.5f, 0.5f}, {});
    EXPECT_NEAR(ray.o.z, 1.f, 1e-6f);
    EXPECT_NEAR(ray.tmax, 999.f, 1e-3f);
}

TEST(Camera, DefaultsWithoutChildren) {
    Properties p("sensor", "perspective", kCameraLoc);
    p.set("fov", "float", 45.0, kCameraLoc);
    auto sensor = std::dynamic_pointer_cast<Sensor>(create_sensor(p));
    EXPECT_EQ(sensor->film().width(), 768);
    EXPECT_EQ(sensor->film().height(), 576);
    EXPECT_EQ(sensor->sample_count(), 4);
    EXPECT_NE(dynamic_cast<const GaussianFilter*>(&sensor->film().filter()), nullptr);
}

void expect_camera_input_error(Properties p, const char* fragment) {
    try {
        create_sensor(p);
        ADD_FAILURE() << "no error; expected '" << fragment << "'";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        EXPECT_EQ(e.location().file, kCameraLoc.file);
    }
}

TEST(Camera, RejectsBadParameters) {
    {
        Properties p = sensor_props("perspective", 8, 8);
        p.set("fov", "float", 45.0, kCameraLoc);
        p.set("focal_length", "string", std::string("50mm"), kCameraLoc);
        expect_camera_input_error(p, "either");
    }
    for (double fov : {0.0, 180.0, -5.0}) {
        Properties p = sensor_props("perspective", 8, 8);
        p.set("fov", "float", fov, kCameraLoc);
        expect_camera_input_error(p, "field of view");
    }
    {
        Properties p = sensor_props("perspective", 8, 8);
        p.set("fov", "float", 45.0, kCameraLoc);
        p.set("fov_axis", "string", std::string("z"), kCameraLoc);
        expect_camera_input_error(p, "fov_axis");
    }
    {
        Properties p = sensor_props("perspective", 8, 8);
        p.set("near_clip", "float", 0.0, kCameraLoc);
        expect_camera_input_error(p, "near_clip");
    }
    {
        Properties p = sensor_props("orthographic", 8, 8);
        p.set("near_clip", "float", 2.0, kCameraLoc);
        p.set("far_clip", "float", 1.0, kCameraLoc);
        expect_camera_input_error(p, "far_clip");
    }
    {
        Properties p = sensor_props("perspective", 8, 8);
        p.set("to_world", "transform", Transform::scale({2, 2, 2}), kCameraLoc);
        expect_camera_input_error(p, "scale");
    }
    {
        Matrix4 shear = Matrix4::identity();
        shear.m[0][1] = 0.5;
        Properties p = sensor_props("perspective", 8, 8);
        p.set("to_world", "transform", Transform(shear), kCameraLoc);
        expect_camera_input_error(p, "scale");
    }
    expect_camera_input_error(Properties("sensor", "radiancemeter", kCameraLoc), "unsupported sensor plugin 'radiancemeter' (supported: perspective, thinlens, orthographic)");
}

TEST(Camera, PrincipalPointOffsetShiftsTheImage) {
    Properties p = sensor_props("perspective", 40, 20);
    p.set("fov", "float", 50.0, kCameraLoc);
    p.set("principal_point_offset_x", "float", 0.1, kCameraLoc);
    p.set("principal_point_offset_y", "float", -0.2, kCameraLoc);
    auto sensor = std::dynamic_pointer_cast<Sensor>(create_sensor(p));
    p.check_all_used();
    // The optical axis now passes through film position (0.5 - 0.1, 0.5 + 0.2).
    Vec3f d = sensor->sample_ray({0.4f, 0.7f}, {}).first.d;
    EXPECT_NEAR(d.x, 0.f, 1e-6f);
    EXPECT_NEAR(d.y, 0.f, 1e-6f);
}

TEST(Camera, PerspectiveAllowsAMirror) {
    Properties p = sensor_props("perspective", 8, 8);
    p.set("to_world", "transform", Transform::scale({-1, 1, 1}), kCameraLoc);
    auto sensor = std::dynamic_pointer_cast<Sensor>(create_sensor(p));
    EXPECT_LT(sensor->sample_ray({0.1f, 0.5f}, {}).first.d.x, 0.f);  // image left is now camera -x
}

TEST(Camera, OrthographicExtentsFollowToWorldScale) {
    // Film 40 x 20 (aspect 2): camera space x in [-1, 1], y in [-0.5, 0.5], scaled by (3, 3, 1).
    OrthographicCamera cam(film(40, 20), Transform::translate({0, 0, -2}) * Transform::scale({3, 3, 1}), 0.5f,
                           10.f);
    auto corner = cam.sample_ray({0.f, 0.f}, {}).first;
    EXPECT_NEAR(corner.o.x, 3.f, 1e-5f);  // left = +x
    EXPECT_NEAR(corner.o.y, 1.5f, 1e-5f);
    EXPECT_NEAR(corner.o.z, -1.5f, 1e-5f);  // near plane at z = 0.5 before the translation
    EXPECT_EQ(corner.d, Vec3f(0.f, 0.f, 1.f));
    EXPECT_NEAR(corner.tmax, 9.5f, 1e-5f);
    auto other = cam.sample_ray({1.f, 1.f}, {}).first;
    EXPECT_NEAR(other.o.x, -3.f, 1e-5f);
    EXPECT_NEAR(other.o.y, -1.5f, 1e-5f);
    auto centre = cam.sample_ray({0.5f, 0.5f}, {}).first;
    EXPECT_NEAR(centre.o.x, 0.f, 1e-6f);
    EXPECT_NEAR(centre.o.y, 0.f, 1e-6f);

    // Through the factory, with a lookat: rays are parallel to the view direction.
    Properties p = sensor_props("orthographic", 16, 16);
    p.set("to_world", "transform", Transform::look_at({0, 5, 0}, {0, 0, 0}, {0, 0, 1}), kCameraLoc);
    auto sensor = std::dynamic_pointer_cast<Sensor>(create_sensor(p));
    p.check_all_used();
    auto r = sensor->sample_ray({0.3f, 0.8f}, {}).first;
    EXPECT_NEAR(r.d.y, -1.f, 1e-6f);
}

TEST(Film, HdrfilmParameters) {
    Properties f("film", "hdrfilm", kCameraLoc);
    f.set("width", "integer", int64_t(48), kCameraLoc);
    f.set("height", "integer", int64_t(32), kCameraLoc);
    f.set("pixel_format", "string", std::string("rgb"), kCameraLoc);
    f.set("component_format", "string", std::string("float32"), kCameraLoc);
    Properties rf("rfilter", "tent", kCameraLoc);
    f.set("", "rfilter", create_rfilter(rf), kCameraLoc);
    auto film = std::dynamic_pointer_cast<Film>(create_film(f));
    f.check_all_used();
    EXPECT_EQ(film->width(), 48);
    EXPECT_EQ(film->height(), 32);
    EXPECT_NE(dynamic_cast<const TentFilter*>(&film->filter()), nullptr);
    EXPECT_FALSE(film->sample_border());

    Properties crop("film", "hdrfilm", kCameraLoc);
    crop.set("crop_width", "integer", int64_t(4), SourceLocation{"camera_test.xml", 12});
    try {
        create_film(crop);
        ADD_FAILURE() << "cropping must be rejected";
    } catch (const InputError& e) {
        EXPECT_EQ(e.location().line, 12);
        EXPECT_NE(std::string(e.what()).find("not supported"), std::string::npos);
    }
    Properties bad("film", "hdrfilm", kCameraLoc);
    bad.set("width", "integer", int64_t(0), kCameraLoc);
    EXPECT_THROW(create_film(bad), InputError);
    EXPECT_THROW(create_film(Properties("film", "specfilm", kCameraLoc)), InputError);
}

TEST(Sampler, CountsSeedsAndOtherTypes) {
    Properties p("sampler", "stratified", kCameraLoc);
    p.set("sample_count", "integer", int64_t(10), kCameraLoc);
    p.set("jitter", "boolean", true, kCameraLoc);
    std::vector<std::string> warnings;
    auto previous =
        set_warning_handler([&](const SourceLocation&, const std::string& m) { warnings.push_back(m); });
    auto s = std::dynamic_pointer_cast<SamplerSettings>(create_sampler(p));
    p.check_all_used();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("independently"), std::string::npos);
    EXPECT_EQ(s->sample_count, 16);  // Mitsuba rounds stratified counts up to a square
    Properties ld("sampler", "ldsampler", kCameraLoc);
    ld.set("sample_count", "integer", int64_t(20), kCameraLoc);
    EXPECT_EQ(std::dynamic_pointer_cast<SamplerSettings>(create_sampler(ld))->sample_count, 32);
    Properties bad("sampler", "independent", kCameraLoc);
    bad.set("sample_count", "integer", int64_t(0), kCameraLoc);
    EXPECT_THROW(create_sampler(bad), InputError);
    EXPECT_THROW(create_sampler(Properties("sampler", "sobol", kCameraLoc)), InputError);
    set_warning_handler(previous);
}

}  // namespace
}  // namespace volguide
