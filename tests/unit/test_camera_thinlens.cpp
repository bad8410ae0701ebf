// Mitsuba 3's `thinlens` (issue 40): rays leave from the aperture disk of aperture_radius and pass
// through the point of the focal plane (camera z = focus_distance) that the pinhole ray through the
// same film position reaches; the pinhole layout of random numbers is kept for `perspective`.
#include <gtest/gtest.h>

#include <cmath>

#include "volguide/core/properties.h"
#include "volguide/render/sensors/hdrfilm.h"
#include "volguide/render/sensors/rfilters.h"
#include "volguide/render/sensor.h"
#include "volguide/scene/factories.h"

namespace volguide {
namespace {

const SourceLocation kLoc{"thinlens_test.xml", 3};

Properties lens_props(const std::string& type) {
    Properties p("sensor", type, kLoc);
    p.set("", "film", std::make_shared<Film>(32, 16, std::make_shared<BoxFilter>()), kLoc);
    p.set("fov", "float", 50.0, kLoc);
    p.set("near_clip", "float", 0.01, kLoc);
    return p;
}

std::shared_ptr<Sensor> make(Properties& p) {
    auto s = std::dynamic_pointer_cast<Sensor>(create_sensor(p));
    p.check_all_used();
    return s;
}

TEST(ThinLens, RaysMeetOnTheFocalPlane) {
    Properties p = lens_props("thinlens");
    p.set("aperture_radius", "float", 0.25, kLoc);
    p.set("focus_distance", "float", 3.0, kLoc);
    auto lens = make(p);
    Properties q = lens_props("perspective");
    auto pinhole = make(q);
    ASSERT_TRUE(lens->needs_aperture_sample());
    EXPECT_FALSE(pinhole->needs_aperture_sample());
    for (Point2f film : {Point2f(0.5f, 0.5f), Point2f(0.1f, 0.8f), Point2f(0.93f, 0.2f)}) {
        const Ray ref = pinhole->sample_ray(film, {0.5f, 0.5f}).first;
        // The pinhole ray reaches the focal plane z = 3 (camera = world here) at:
        const Point3f focus = ref.o + ref.d * ((3.f - ref.o.z) / ref.d.z);
        float max_offset = 0.f;
        for (Point2f u : {Point2f(0.1f, 0.2f), Point2f(0.9f, 0.5f), Point2f(0.3f, 0.95f)}) {
            const Ray r = lens->sample_ray(film, u).first;
            const Point3f hit = r.o + r.d * ((3.f - r.o.z) / r.d.z);
            EXPECT_NEAR(hit.x, focus.x, 1e-4f);
            EXPECT_NEAR(hit.y, focus.y, 1e-4f);
            // The origin (moved to the near plane) stays within the aperture disk.
            const Point3f lens_point = r.o - r.d * (0.01f / r.d.z);
            EXPECT_LE(std::hypot(lens_point.x, lens_point.y), 0.25f + 1e-5f);
            max_offset = std::max(max_offset, std::hypot(lens_point.x, lens_point.y));
        }
        EXPECT_GT(max_offset, 0.1f);  // the aperture sample does move the origin
    }
}

TEST(ThinLens, ApertureRadiusRequiredAndPositive) {
    Properties p = lens_props("thinlens");
    EXPECT_THROW(make(p), InputError);
    Properties z = lens_props("thinlens");
    z.set("aperture_radius", "float", 0.0, kLoc);
    EXPECT_THROW(make(z), InputError);
}

}  // namespace
}  // namespace volguide
