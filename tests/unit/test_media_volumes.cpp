// Volumes: Mitsuba's .vol format and grid conventions (voxel centres at (i + 0.5) / res, clamping,
// unit cube under to_world, use_grid_bbox), the linear-ramp oracle (oracles.md §4: tau = sigma0 / 2
// along +x), constvolume, and file:line errors for unreadable, truncated, wrong-magic or invalid files.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "support/vol_writer.h"
#include "media_loading_util.h"
#include "volguide/core/log.h"
#include "volguide/media/heterogeneous.h"
#include "volguide/media/volume.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// Warnings raised while alive (the log handler's messages).
class CapturedWarnings {
  public:
    CapturedWarnings() {
        previous_ = set_warning_handler([this](const SourceLocation&, const std::string& m) { list.push_back(m); });
    }
    ~CapturedWarnings() { set_warning_handler(previous_); }
    std::vector<std::string> list;

  private:
    WarningHandler previous_;
};

}  // namespace

TEST(MediaVolumes, LinearRampGivesHalfSigma0) {
    ScratchDir dir;
    const float sigma0 = 3.f;
    write_vol_file(dir.path("ramp.vol"), make_vol_grid(8, 5, 3, 1, [&](float x, float, float, int) {
                       return sigma0 * x;
                   }));
    std::string path = dir.write("s.xml", scene(R"(<medium type="heterogeneous">
    <volume name="sigma_t" type="gridvolume"><string name="filename" value="ramp.vol"/></volume>
    <float name="albedo" value="0"/>
</medium>
)"));
    auto m = first<HeterogeneousMedium>(load_scene_properties(path), "medium");
    ASSERT_TRUE(m);
    // Trilinear interpolation between voxel centres is exact inside; the clamped half voxels at
    // both ends err by +h^2/2 and -h^2/2 and cancel, so the crossing has tau = sigma0 / 2 exactly.
    for (float y : {0.1f, 0.5f, 0.93f}) {
        EXPECT_NEAR(optical_depth(*m, Point3f(-0.5f, y, 0.4f), Vec3f(1, 0, 0), 2.0), sigma0 / 2, 1e-4) << y;
    }
    // Inside, sigma(x) = sigma0 x between the first and last voxel centres.
    EXPECT_NEAR(m->eval(Point3f(0.3f, 0.5f, 0.5f)).sigma_t.r, sigma0 * 0.3f, 1e-5f);
    EXPECT_NEAR(m->eval(Point3f(0.03f, 0.5f, 0.5f)).sigma_t.r, sigma0 / 16, 1e-5f);  // clamped to 1st centre
    EXPECT_EQ(m->eval(Point3f(1.01f, 0.5f, 0.5f)).sigma_t.r, 0.f);  // outside the unit cube: no medium
}

TEST(MediaVolumes, ToWorldAndGridBBox) {
    ScratchDir dir;
    VolGrid g = make_vol_grid(4, 4, 4, 1, [](float x, float, float, int) { return 2.f * x; });
    g.bbox[0] = -1, g.bbox[1] = -1, g.bbox[2] = -1, g.bbox[3] = 1, g.bbox[4] = 1, g.bbox[5] = 1;
    write_vol_file(dir.path("g.vol"), g);
    // Without use_grid_bbox the file's bbox is ignored: unit cube scaled by 2 along x -> [0, 2].
    std::string a = dir.write("a.xml", scene(R"(<medium type="heterogeneous">
    <volume name="sigma_t" type="gridvolume"><string name="filename" value="g.vol"/>
        <transform name="to_world"><scale x="2"/></transform></volume>
</medium>
)"));
    auto ma = first<HeterogeneousMedium>(load_scene_properties(a), "medium");
    EXPECT_NEAR(ma->bbox().lo.x, 0.f, 1e-6f);
    EXPECT_NEAR(ma->bbox().hi.x, 2.f, 1e-6f);
    EXPECT_NEAR(optical_depth(*ma, Point3f(-1.f, 0.5f, 0.5f), Vec3f(1, 0, 0), 4.0), 2.0, 1e-4);
    // With it, the grid spans the file's bbox [-1, 1]^3, then to_world (translate by 3 in y).
    std::string b = dir.write("b.xml", scene(R"(<medium type="heterogeneous">
    <volume name="sigma_t" type="gridvolume"><string name="filename" value="g.vol"/>
        <boolean name="use_grid_bbox" value="true"/>
        <transform name="to_world"><translate y="3"/></transform></volume>
</medium>
)"));
    auto mb = first<HeterogeneousMedium>(load_scene_properties(b), "medium");
    EXPECT_NEAR(mb->bbox().lo.y, 2.f, 1e-6f);
    EXPECT_NEAR(mb->bbox().hi.y, 4.f, 1e-6f);
    EXPECT_NEAR(mb->bbox().lo.x, -1.f, 1e-6f);
    EXPECT_NEAR(optical_depth(*mb, Point3f(-2.f, 3.f, 0.f), Vec3f(1, 0, 0), 4.0), 2.0, 1e-4);
}

TEST(MediaVolumes, VoxelCentresNearestAndChannels) {
    ScratchDir dir;
    // 3-channel grid: voxel (x, y, z) holds (x, y, z + 10).
    VolGrid g;
    g.nx = 2, g.ny = 3, g.nz = 4, g.channels = 3;
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 2; ++x) g.values.insert(g.values.end(), {float(x), float(y), float(z + 10)});
    write_vol_file(dir.path("c.vol"), g);
    auto nearest = load_volume(dir, R"(<volume type="gridvolume"><string name="filename" value="c.vol"/>
    <string name="filter_type" value="nearest"/></volume>
)");
    ASSERT_TRUE(nearest);
    EXPECT_EQ(nearest->eval(Point3f(0.49f, 0.34f, 0.76f)), Color3(0.f, 1.f, 13.f));
    EXPECT_EQ(nearest->eval(Point3f(0.51f, 0.99f, 0.01f)), Color3(1.f, 2.f, 10.f));
    EXPECT_EQ(nearest->max_value(), 13.f);
    auto tri = load_volume(dir, R"(<volume type="gridvolume"><string name="filename" value="c.vol"/></volume>
)");
    // At a voxel centre the trilinear value is the voxel; halfway between centres the mean.
    EXPECT_EQ(tri->eval(Point3f(0.25f, 0.5f, 0.375f)), Color3(0.f, 1.f, 11.f));
    const Color3 mid = tri->eval(Point3f(0.5f, 0.5f, 0.5f));
    EXPECT_NEAR(mid.r, 0.5f, 1e-6f);
    EXPECT_NEAR(mid.b, 11.5f, 1e-5f);
    // Clamped outside.
    EXPECT_EQ(tri->eval(Point3f(-3.f, 0.5f, 0.375f)), Color3(0.f, 1.f, 11.f));
    // Repeat wraps the index.
    auto rep = load_volume(dir, R"(<volume type="gridvolume"><string name="filename" value="c.vol"/>
    <string name="filter_type" value="nearest"/><string name="wrap_mode" value="repeat"/></volume>
)");
    EXPECT_EQ(rep->eval(Point3f(1.25f, 0.5f, 0.375f)), Color3(0.f, 1.f, 11.f));
}

TEST(MediaVolumes, ConstVolumeSpansTheUnitCubeUnderToWorld) {
    ScratchDir dir;
    auto v = load_volume(dir, R"(<volume type="constvolume"><rgb name="value" value="0.5, 0.4, 0.3"/>
    <transform name="to_world"><translate x="-0.5" y="-0.5" z="-0.5"/></transform></volume>
)");
    ASSERT_TRUE(v);
    EXPECT_EQ(v->eval(Point3f(0.f)), Color3(0.5f, 0.4f, 0.3f));
    EXPECT_FLOAT_EQ(v->max_value(), 0.5f);  // a true bound (Mitsuba's constvolume reports the mean)
    EXPECT_NEAR(v->bbox().lo.x, -0.5f, 1e-6f);
    EXPECT_NEAR(v->bbox().hi.z, 0.5f, 1e-6f);
}

TEST(MediaVolumes, BadFilesAreInputErrorsNamingTheFile) {
    ScratchDir dir;
    VolGrid g = make_vol_grid(2, 2, 2, 1, [](float, float, float, int) { return 1.f; });
    write_vol_file(dir.path("magic.vol"), g, "VOX");
    write_vol_file(dir.path("version.vol"), g, "VOL", 2);
    write_vol_file(dir.path("encoding.vol"), g, "VOL", 3, 2);
    write_vol_file(dir.path("trunc.vol"), g, "VOL", 3, 1, 4);
    write_vol_file(dir.path("header.vol"), g, "VOL", 3, 1, 40);
    VolGrid neg = g;
    neg.values[5] = -0.5f;
    write_vol_file(dir.path("neg.vol"), neg);
    VolGrid nan = g;
    nan.values[2] = std::nanf("");
    write_vol_file(dir.path("nan.vol"), nan);
    dir.write("text.vol", "hello");
    struct Case {
        const char* file;
        const char* needle;
    } cases[] = {{"magic.vol", "magic"},        {"version.vol", "version"}, {"encoding.vol", "encoding"},
                 {"trunc.vol", "truncated"},    {"header.vol", "truncated"}, {"neg.vol", "invalid value -0.5"},
                 {"nan.vol", "invalid value"}, {"text.vol", "truncated"}};
    for (const Case& c : cases) {
        std::string xml = dir.write("e.xml", scene(std::string("<volume type=\"gridvolume\">\n<string name=\"filename\" value=\"") +
                                                   c.file + "\"/>\n</volume>\n"));
        expect_input_error([&] { load_scene_properties(xml); }, xml, 3, c.needle);
        try {
            load_scene_properties(xml);
        } catch (const InputError& e) {
            EXPECT_NE(e.message().find(c.file), std::string::npos) << e.what();
        }
    }
    // Unreadable (a directory with the name of a file).
    std::filesystem::create_directories(dir.path("dir.vol"));
    std::string xml = dir.write("d.xml", scene("<volume type=\"gridvolume\">\n<string name=\"filename\" value=\"dir.vol\"/>\n</volume>\n"));
    EXPECT_THROW(load_scene_properties(xml), InputError);
    // An albedo grid above 1 and a gridvolume sigma_t in a homogeneous medium.
    VolGrid big = make_vol_grid(2, 2, 2, 1, [](float, float, float, int) { return 1.5f; });
    write_vol_file(dir.path("big.vol"), big);
    std::string al = dir.write("al.xml", scene(R"(<medium type="heterogeneous">
<volume name="albedo" type="gridvolume"><string name="filename" value="big.vol"/></volume>
</medium>
)"));
    expect_input_error([&] { load_scene_properties(al); }, al, 3, "albedo");
    std::string hs = dir.write("hs.xml", scene(R"(<medium type="homogeneous">
<volume name="sigma_t" type="gridvolume"><string name="filename" value="big.vol"/></volume>
</medium>
)"));
    expect_input_error([&] { load_scene_properties(hs); }, hs, 3, "constant");
}

TEST(MediaVolumes, WrittenVolFilesReadBackExactly) {
    ScratchDir dir;
    GridData g;
    g.nx = 3, g.ny = 2, g.nz = 4, g.channels = 3;
    g.bbox = BBox3f(Point3f(-1.f, 0.f, 2.f), Point3f(1.f, 0.5f, 3.f));
    for (size_t i = 0; i < size_t(3 * 2 * 4 * 3); ++i) g.values.push_back(0.25f * float(i));
    const std::string path = dir.path("w.vol");
    write_vol_file(path, g);
    const GridData back = read_vol_file(path);
    EXPECT_EQ(back.nx, 3);
    EXPECT_EQ(back.ny, 2);
    EXPECT_EQ(back.nz, 4);
    EXPECT_EQ(back.channels, 3);
    EXPECT_EQ(back.values, g.values);
    EXPECT_EQ(back.bbox.lo, g.bbox.lo);
    EXPECT_EQ(back.bbox.hi, g.bbox.hi);
    g.values.pop_back();
    EXPECT_THROW(write_vol_file(path, g), std::runtime_error);
}

// Some tools write -0, negative denormals (-1e-45) and float noise (-1.28e-38, a normal float) for empty
// voxels; Mitsuba 0.6 renders them as 0. They read as 0 with one warning for the file (through the log
// handler); a clearly negative density stays an error.
TEST(MediaVolumes, NegativeFloatNoiseReadsAsZeroWithOneWarning) {
    ScratchDir dir;
    VolGrid g = make_vol_grid(2, 2, 2, 1, [](float, float, float, int) { return 1.f; });
    g.values[1] = -0.f;
    g.values[2] = -1e-45f;
    g.values[5] = -1.28e-38f;
    ASSERT_GE(std::fabs(g.values[5]), std::numeric_limits<float>::min());  // a normal float, not a denormal
    g.values[6] = -1e-20f;
    write_vol_file(dir.path("zeros.vol"), g);
    CapturedWarnings warnings;
    auto v = load_volume(dir, R"(<volume type="gridvolume"><string name="filename" value="zeros.vol"/>
    <string name="filter_type" value="nearest"/></volume>
)");
    ASSERT_TRUE(v);
    ASSERT_EQ(warnings.list.size(), 1u);
    EXPECT_NE(warnings.list[0].find("zeros.vol"), std::string::npos) << warnings.list[0];
    EXPECT_NE(warnings.list[0].find("4 negative value(s)"), std::string::npos) << warnings.list[0];
    // Voxel 1 is (1, 0, 0), voxel 2 (0, 1, 0), voxel 5 (1, 0, 1): 0, not negative; the others keep 1.
    for (const Point3f& p : {Point3f(0.75f, 0.25f, 0.25f), Point3f(0.25f, 0.75f, 0.25f), Point3f(0.75f, 0.25f, 0.75f)}) {
        const Color3 c = v->eval(p);
        EXPECT_EQ(c.r, 0.f);
        EXPECT_FALSE(std::signbit(c.r));
    }
    EXPECT_EQ(v->eval(Point3f(0.25f, 0.25f, 0.25f)).r, 1.f);

    // Voxel 6 (0, 1, 1) too.
    EXPECT_EQ(v->eval(Point3f(0.25f, 0.75f, 0.75f)).r, 0.f);

    // Just beyond the noise bound a value is a density, not a zero: an error naming the file.
    VolGrid negative = g;
    negative.values[3] = -2e-20f;
    write_vol_file(dir.path("negative.vol"), negative);
    const std::string xml = dir.write("e.xml", scene("<volume type=\"gridvolume\">\n<string name=\"filename\" "
                                                     "value=\"negative.vol\"/>\n</volume>\n"));
    expect_input_error([&] { load_scene_properties(xml); }, xml, 3, "invalid value");
}
