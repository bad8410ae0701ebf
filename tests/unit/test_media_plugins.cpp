// The media factory through the XML loader: Mitsuba 3 parameter names and defaults for
// homogeneous/heterogeneous media, phase children and volumes, and file:line errors for bad values.
#include <gtest/gtest.h>

#include "media_loading_util.h"
#include "volguide/media/heterogeneous.h"
#include "volguide/media/homogeneous.h"
#include "volguide/media/phase_hg.h"
#include "volguide/media/phase_isotropic.h"

using namespace volguide;
using namespace volguide::test;

TEST(MediaPlugins, HomogeneousParameters) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene(R"(<medium type="homogeneous" id="m">
    <rgb name="sigma_t" value="1, 0.2, 1"/>
    <rgb name="albedo" value="0.5, 0.5, 0.99"/>
    <float name="scale" value="10"/>
    <boolean name="sample_emitters" value="false"/>
    <phase type="hg"><float name="g" value="0.3"/></phase>
</medium>
)"));
    Properties root = load_scene_properties(path);
    auto m = first<HomogeneousMedium>(root, "medium");
    ASSERT_TRUE(m);
    EXPECT_EQ(m->sigma_t(), Color3(10.f, 2.f, 10.f));
    EXPECT_FALSE(m->sample_emitters());
    EXPECT_TRUE(m->is_homogeneous());
    auto c = m->eval(Point3f(5.f, -3.f, 100.f));
    EXPECT_NEAR(c.sigma_s.r, 5.f, 1e-6f);
    EXPECT_NEAR(c.sigma_s.b, 9.9f, 1e-5f);
    auto hg = std::dynamic_pointer_cast<HGPhase>(m->phase_ptr());
    ASSERT_TRUE(hg);
    EXPECT_FLOAT_EQ(hg->g(), 0.3f);
}

TEST(MediaPlugins, HomogeneousDefaults) {
    ScratchDir dir;
    std::string path = dir.write("s.xml", scene("<medium type=\"homogeneous\"/>\n"));
    auto m = first<HomogeneousMedium>(load_scene_properties(path), "medium");
    ASSERT_TRUE(m);
    EXPECT_EQ(m->sigma_t(), Color3(1.f));  // Mitsuba: sigma_t 1, albedo 0.75, isotropic
    EXPECT_FLOAT_EQ(m->eval(Point3f(0.f)).sigma_s.g, 0.75f);
    EXPECT_TRUE(m->sample_emitters());
    EXPECT_TRUE(std::dynamic_pointer_cast<IsotropicPhase>(m->phase_ptr()));
}

TEST(MediaPlugins, BadValuesAreReportedAtTheirLine) {
    ScratchDir dir;
    auto bad = [&](const std::string& body, int line, const std::string& needle) {
        std::string path = dir.write("bad.xml", scene(body));
        expect_input_error([&] { load_scene_properties(path); }, path, line, needle);
    };
    bad("<medium type=\"homogeneous\">\n<rgb name=\"sigma_t\" value=\"1, -0.2, 1\"/>\n</medium>\n", 3, "sigma_t");
    bad("<medium type=\"homogeneous\">\n<float name=\"albedo\" value=\"1.5\"/>\n</medium>\n", 3, "albedo");
    bad("<medium type=\"heterogeneous\">\n<float name=\"scale\" value=\"-1\"/>\n</medium>\n", 3, "scale");
    bad("<medium type=\"homogeneous\">\n<phase type=\"hg\">\n<float name=\"g\" value=\"1\"/>\n</phase>\n</medium>\n", 4,
        "(-1, 1)");
    bad("<medium type=\"homogeneous\">\n<phase type=\"isotropic\"/>\n<phase type=\"isotropic\"/>\n</medium>\n", 4,
        "at most one phase");
    bad("<medium type=\"homogeneous\">\n<float name=\"sigma_x\" value=\"1\"/>\n</medium>\n", 3, "sigma_x");
    bad("<medium type=\"fog\"/>\n", 2, "fog");
    bad("<volume type=\"gridvolume\">\n<string name=\"filter_type\" value=\"cubic\"/>\n"
        "<string name=\"filename\" value=\"bad.xml\"/>\n</volume>\n",
        3, "cubic");
}
