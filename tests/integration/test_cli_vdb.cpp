// OpenVDB media through the CLI: a heterogeneous medium read from a .vdb file renders the same
// image as the same data read from a Mitsuba .vol file (albedo 0, so each pixel estimates the
// transmittance through the cube; same seed), and a grid name missing from the .vdb file is an
// input error like those of test_cli_bad_input.cpp (exit 1, one line `volguide: FILE:LINE: message`
// listing the grids the file has, no output written).
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>

#include "support/cli.h"
#include "support/vol_writer.h"
#include "volguide/core/image.h"
#include "volguide/render/image_io.h"

using namespace volguide;
using namespace volguide::test;
namespace fs = std::filesystem;

namespace {

constexpr int kRes = 6;

// sigma_t at a point of the grid's unit cube: varies along x and y.
float density(float x, float y, float) {
    return 3.f * x + 1.5f * y * y;
}

// The density sampled at voxel centres as a VDB FloatGrid named `name` whose cells span
// [lo, lo + size]^3 in world space.
void write_density_vdb(const std::string& path, const std::string& name, double lo, double size) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.f);
    grid->setName(name);
    const double h = size / kRes;
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    for (int i = 0; i < 3; ++i) {
        m(i, i) = h;
        m(3, i) = lo + 0.5 * h;
    }
    grid->setTransform(openvdb::math::Transform::createLinearTransform(m));
    auto acc = grid->getAccessor();
    for (int z = 0; z < kRes; ++z)
        for (int y = 0; y < kRes; ++y)
            for (int x = 0; x < kRes; ++x)
                acc.setValue(openvdb::Coord(x, y, z),
                             density((x + 0.5f) / kRes, (y + 0.5f) / kRes, (z + 0.5f) / kRes));
    openvdb::io::File file(path);
    file.write({grid});
    file.close();
}

// A cube [-1, 1]^3 filled with the medium, seen against a white environment. `volume` holds the
// gridvolume's parameters.
std::string vdb_cube_scene(const std::string& volume) {
    return R"(<scene version="3.0.0">
    <integrator type="volpath"><integer name="max_depth" value="8"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="1.5, 2, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/></film>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    <medium type="heterogeneous" id="m">
        <volume name="sigma_t" type="gridvolume">
)" + volume +
           R"(        </volume>
        <float name="albedo" value="0"/>
    </medium>
    <shape type="cube"><bsdf type="null"/><ref name="interior" id="m"/></shape>
</scene>
)";
}

const std::string kUnitCubeToCube =
    R"(            <transform name="to_world"><scale value="2"/><translate x="-1" y="-1" z="-1"/></transform>
)";

Image render_vdb(const TempDir& dir, const std::string& scene_name, const std::string& xml) {
    std::string scene = dir.write(scene_name + ".xml", xml);
    std::string out = dir.file(scene_name + ".exr");
    CliResult r = run_cli({"render", scene, "-o", out, "--seed", "7", "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return read_image(out);
}

double mean(const Image& img) {
    double s = 0.0;
    for (const Color3& c : img.pixels) s += (c.r + c.g + c.b) / 3.0;
    return img.pixels.empty() ? 0.0 : s / double(img.pixels.size());
}

}  // namespace

TEST(CliVdb, VdbMediumRendersLikeTheSameVolData) {
    TempDir dir("vdb-render");
    write_vol_file(dir.file("d.vol"), make_vol_grid(kRes, kRes, kRes, 1, [](float x, float y, float z, int) {
                       return density(x, y, z);
                   }));
    write_density_vdb(dir.file("unit.vdb"), "density", 0.0, 1.0);   // the unit cube
    write_density_vdb(dir.file("placed.vdb"), "smoke", -1.0, 2.0);  // the cube itself

    const std::string file = R"(            <string name="filename" value=")";
    Image vol = render_vdb(dir, "vol", vdb_cube_scene(file + "d.vol\"/>\n" + kUnitCubeToCube));
    Image vdb = render_vdb(dir, "vdb", vdb_cube_scene(file + "unit.vdb\"/>\n" + kUnitCubeToCube));
    Image placed =
        render_vdb(dir, "placed",
               vdb_cube_scene(file + "placed.vdb\"/>\n" + R"(            <string name="grid" value="smoke"/>
            <boolean name="use_grid_bbox" value="true"/>
)"));
    ASSERT_EQ(vol.pixels.size(), vdb.pixels.size());
    ASSERT_EQ(vol.pixels.size(), placed.pixels.size());
    // Not trivial: the environment shows around the cube, the medium absorbs inside it.
    const double m = mean(vol);
    EXPECT_GT(m, 0.2);
    EXPECT_LT(m, 0.9);
    EXPECT_EQ(vol.at(0, 0).r, 1.f);
    // Same data, same unit cube, same seed: the same image.
    for (size_t i = 0; i < vol.pixels.size(); ++i) {
        EXPECT_FLOAT_EQ(vdb.pixels[i].r, vol.pixels[i].r) << i;
    }
    // Placed by the VDB transform instead of to_world: the same medium up to float rounding.
    CliResult d = run_cli({"diff", dir.file("placed.exr"), dir.file("vol.exr"), "--json"});
    ASSERT_EQ(d.exit_code, 0) << d.err;
    auto j = nlohmann::json::parse(d.out);
    EXPECT_NEAR(j["ratio"].get<double>(), 1.0, 2e-3) << d.out;
    EXPECT_LT(j["relmse_1e-2"].get<double>(), 1e-3) << d.out;
    EXPECT_NEAR(mean(placed), m, 2e-3 * m);
}

TEST(CliVdb, MissingGridNameExitsOneWithFileLineAndNoOutput) {
    TempDir dir("bad-vdb_missing_grid");
    write_density_vdb(dir.file("smoke.vdb"), "smoke", 0.0, 1.0);
    // The filename is on line 12 of the scene.
    std::string scene =
        dir.write("scene.xml", vdb_cube_scene(R"(            <string name="filename" value="smoke.vdb"/>
)"));
    std::string out = dir.write("out.exr", "sentinel");
    CliResult r = run_cli({"render", scene, "-o", out, "--quiet"});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    ASSERT_FALSE(r.err.empty());
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    EXPECT_TRUE(std::regex_search(r.err, std::regex("^volguide: .*scene\\.xml:12: .+\n$"))) << r.err;
    for (const char* needle : {"smoke.vdb", "\"density\"", "\"smoke\""})
        EXPECT_NE(r.err.find(needle), std::string::npos) << needle << " in " << r.err;
    EXPECT_EQ(read_file(out), "sentinel");
    EXPECT_FALSE(fs::exists(dir.file("out_var.exr")));
    EXPECT_FALSE(fs::exists(dir.file("scene.exr")));
}
