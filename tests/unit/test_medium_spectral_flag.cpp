// `has_spectral_extinction` on homogeneous media (issue 40): accepted with Mitsuba's meaning when the
// extinction is gray (the same image either way), refused at its line for a chromatic extinction
// (Mitsuba would then render one channel's unweighted estimate, which volguide does not reproduce).
#include <gtest/gtest.h>

#include "media_loading_util.h"
#include "volguide/media/homogeneous.h"

using namespace volguide;
using namespace volguide::test;

TEST(MediaPlugins, HasSpectralExtinction) {
    ScratchDir dir;
    std::string gray = dir.write("gray.xml", scene(R"(<medium type="homogeneous">
    <float name="sigma_t" value="5"/>
    <float name="scale" value="200"/>
    <boolean name="has_spectral_extinction" value="false"/>
</medium>
)"));
    auto m = first<HomogeneousMedium>(load_scene_properties(gray), "medium");
    ASSERT_TRUE(m);
    EXPECT_EQ(m->sigma_t(), Color3(1000.f));
    std::string spectral = dir.write("on.xml", scene(R"(<medium type="homogeneous">
    <rgb name="sigma_t" value="1, 2, 3"/>
    <boolean name="has_spectral_extinction" value="true"/>
</medium>
)"));
    EXPECT_TRUE(first<HomogeneousMedium>(load_scene_properties(spectral), "medium"));
    std::string bad = dir.write("bad.xml", scene("<medium type=\"homogeneous\">\n<rgb name=\"sigma_t\" value=\"1, 2, 3\"/>\n"
                                                 "<boolean name=\"has_spectral_extinction\" value=\"false\"/>\n</medium>\n"));
    expect_input_error([&] { load_scene_properties(bad); }, bad, 4, "needs a gray sigma_t");
}
