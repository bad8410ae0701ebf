// White furnace (oracles.md §1) with the REAL media plugins: a constant environment of radiance 1
// around a sphere holding an albedo-1 medium, homogeneous or heterogeneous (a chromatic
// gridvolume with strongly varying extinction), g in {0, 0.9, -0.5}, behind a null or a smooth
// dielectric boundary. Every pixel has mean exactly 1; the image mean is checked within 4 standard
// errors (and every 6x6 block within 5): at these budgets (SE about 0.0011-0.0015) an albedo of 0.98
// instead of 1 fails every case (measured), so a bias of about 0.5 % is resolved.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>

#include "support/furnace_grid.h"
#include "support/volpath_test_util.h"

using namespace volguide;
using namespace volguide::test;

namespace {

struct FurnaceCase {
    const char* name;
    bool heterogeneous;
    float g;
    const char* boundary;  // the sphere's BSDF
    int spp;
};

std::string media_furnace_xml(const FurnaceCase& c, const std::string& grid_path) {
    const std::string sigma_t =
        c.heterogeneous
            ? fmt::format(R"(<volume type="gridvolume" name="sigma_t"><string name="filename" value="{}"/>
                 <transform name="to_world"><scale value="2"/><translate value="-1, -1, -1"/></transform></volume>)",
                          grid_path)
            : std::string(R"(<rgb name="sigma_t" value="2, 1, 3"/>)");
    return fmt::format(R"(<scene version="3.0.0">
    <integrator type="moment"><integrator type="volpath"/></integrator>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <medium type="{0}" id="m">
        {1}
        <rgb name="albedo" value="1"/>
        <phase type="hg"><float name="g" value="{2}"/></phase>
    </medium>
    <shape type="sphere"><bsdf type="{3}"/><ref name="interior" id="m"/></shape>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="12"/><integer name="height" value="12"/>
            <rfilter type="box"/></film>
    </sensor>
</scene>)",
                       c.heterogeneous ? "heterogeneous" : "homogeneous", sigma_t, c.g, c.boundary);
}

void PrintTo(const FurnaceCase& c, std::ostream* os) { *os << c.name; }

class MediaFurnace : public ::testing::TestWithParam<FurnaceCase> {};

}  // namespace

TEST_P(MediaFurnace, EveryPixelIsOne) {
    const FurnaceCase& c = GetParam();
    TempDir dir("media-furnace");
    const std::string grid = write_furnace_grid(dir);
    Rendered r = render_scene_xml(media_furnace_xml(c, grid), c.spp, 17, /*test_media=*/false);
    expect_constant_image(r, 1.0);
}

INSTANTIATE_TEST_SUITE_P(
    RealMedia, MediaFurnace,
    ::testing::Values(FurnaceCase{"HomogeneousIsotropicNull", false, 0.f, "null", 256},
                      FurnaceCase{"HomogeneousForwardNull", false, 0.9f, "null", 256},
                      FurnaceCase{"HomogeneousBackwardNull", false, -0.5f, "null", 256},
                      FurnaceCase{"HomogeneousIsotropicDielectric", false, 0.f, "dielectric", 512},
                      FurnaceCase{"HomogeneousForwardDielectric", false, 0.9f, "dielectric", 512},
                      FurnaceCase{"HomogeneousBackwardDielectric", false, -0.5f, "dielectric", 512},
                      FurnaceCase{"HeterogeneousIsotropicNull", true, 0.f, "null", 256},
                      FurnaceCase{"HeterogeneousForwardNull", true, 0.9f, "null", 256},
                      FurnaceCase{"HeterogeneousBackwardNull", true, -0.5f, "null", 256},
                      FurnaceCase{"HeterogeneousIsotropicDielectric", true, 0.f, "dielectric", 512},
                      FurnaceCase{"HeterogeneousForwardDielectric", true, 0.9f, "dielectric", 512},
                      FurnaceCase{"HeterogeneousBackwardDielectric", true, -0.5f, "dielectric", 512}),
    [](const auto& info) { return std::string(info.param.name); });
