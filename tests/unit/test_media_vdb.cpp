// OpenVDB grids in `gridvolume` (volguide's extension): .vdb files written here with the OpenVDB
// API must give the same volume as the same data in a Mitsuba .vol file (the linear-ramp oracle of
// oracles.md §4, tau = sigma0 / 2 along +x), use_grid_bbox must place the grid where its VDB
// transform puts it (voxel centres at integer index coordinates), inactive voxels read as the
// background, and bad files, grid names, grid types and transforms are InputErrors naming the file.
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "support/vol_writer.h"
#include "media_loading_util.h"
#include "volguide/media/grid_data.h"
#include "volguide/media/heterogeneous.h"
#include "volguide/media/vdb_header_check.h"
#include "volguide/media/volume.h"

using namespace volguide;
using namespace volguide::test;

namespace {


std::string file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_vdb(const std::string& path, const openvdb::GridPtrVec& grids) {
    openvdb::initialize();
    openvdb::io::File file(path);
    file.write(grids);
    file.close();
}

// A float grid holding f at every voxel of index [0, nx) x [0, ny) x [0, nz), named `name`, with
// voxel size h (per axis) and voxel (0, 0, 0) centred at `origin`.
openvdb::FloatGrid::Ptr float_grid(const std::string& name, int nx, int ny, int nz, const openvdb::Vec3d& h,
                                   const openvdb::Vec3d& origin, const std::function<float(int, int, int)>& f,
                                   float background = 0.f) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(background);
    grid->setName(name);
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    for (int i = 0; i < 3; ++i) {
        m(i, i) = h[i];
        m(3, i) = origin[i];
    }
    grid->setTransform(openvdb::math::Transform::createLinearTransform(m));
    auto acc = grid->getAccessor();
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x) acc.setValue(openvdb::Coord(x, y, z), f(x, y, z));
    return grid;
}

}  // namespace

TEST(MediaVdb, LinearRampMatchesVolFileAndGivesHalfSigma0) {
    ScratchDir dir;
    const float sigma0 = 3.f;
    const int nx = 8, ny = 5, nz = 3;
    // The same data as a .vol file (values at voxel centres (i + 0.5) / n of the unit cube) and as a
    // VDB grid whose voxel (i, j, k) is centred at ((i + 0.5) / nx, (j + 0.5) / ny, (k + 0.5) / nz).
    write_vol_file(dir.path("ramp.vol"),
                   make_vol_grid(nx, ny, nz, 1, [&](float x, float, float, int) { return sigma0 * x; }));
    write_vdb(dir.path("ramp.vdb"),
              {float_grid("density", nx, ny, nz, openvdb::Vec3d(1.0 / nx, 1.0 / ny, 1.0 / nz),
                          openvdb::Vec3d(0.5 / nx, 0.5 / ny, 0.5 / nz),
                          [&](int x, int, int) { return sigma0 * (x + 0.5f) / nx; })});
    auto load = [&](const std::string& file) {
        std::string path = dir.write("s.xml", scene(R"(<medium type="heterogeneous">
    <volume name="sigma_t" type="gridvolume"><string name="filename" value=")" +
                                                    file + R"("/></volume>
    <float name="albedo" value="0"/>
</medium>
)"));
        return first<HeterogeneousMedium>(load_scene_properties(path), "medium");
    };
    auto vol = load("ramp.vol");
    auto vdb = load("ramp.vdb");
    ASSERT_TRUE(vol);
    ASSERT_TRUE(vdb);
    for (float y : {0.1f, 0.5f, 0.93f}) {
        EXPECT_NEAR(optical_depth(*vdb, Point3f(-0.5f, y, 0.4f), Vec3f(1, 0, 0), 2.0), sigma0 / 2, 1e-4) << y;
    }
    for (const Point3f& p :
         {Point3f(0.3f, 0.5f, 0.5f), Point3f(0.03f, 0.2f, 0.9f), Point3f(0.97f, 0.7f, 0.1f),
          Point3f(0.5f, 0.5f, 0.5f), Point3f(0.71f, 0.01f, 0.33f), Point3f(1.01f, 0.5f, 0.5f)}) {
        EXPECT_FLOAT_EQ(vdb->eval(p).sigma_t.r, vol->eval(p).sigma_t.r) << p.x << " " << p.y << " " << p.z;
    }
    EXPECT_NEAR(vdb->eval(Point3f(0.3f, 0.5f, 0.5f)).sigma_t.r, sigma0 * 0.3f, 1e-5f);
    EXPECT_EQ(vdb->bbox().lo.x, vol->bbox().lo.x);
    EXPECT_EQ(vdb->bbox().hi.z, vol->bbox().hi.z);
    // With use_grid_bbox the VDB's own placement is the unit cube too: the same medium.
    std::string path = dir.write("b.xml", scene(R"(<medium type="heterogeneous">
    <volume name="sigma_t" type="gridvolume"><string name="filename" value="ramp.vdb"/>
        <boolean name="use_grid_bbox" value="true"/></volume>
    <float name="albedo" value="0"/>
</medium>
)"));
    auto placed = first<HeterogeneousMedium>(load_scene_properties(path), "medium");
    EXPECT_NEAR(placed->bbox().lo.x, 0.f, 1e-6f);
    EXPECT_NEAR(placed->bbox().hi.x, 1.f, 1e-6f);
    EXPECT_NEAR(placed->bbox().hi.y, 1.f, 1e-6f);
    EXPECT_NEAR(optical_depth(*placed, Point3f(-0.5f, 0.5f, 0.4f), Vec3f(1, 0, 0), 2.0), sigma0 / 2, 1e-4);
}

TEST(MediaVdb, GridBBoxFollowsTheVdbTransform) {
    ScratchDir dir;
    // Voxel size 0.5; active voxels at index x in [-2, 1], y in [0, 2], z in [3, 4]; index (0,0,0) at
    // world (10, -2, 1). Voxel value 100 x + 10 y + z (index), + 1000 to keep it positive.
    const openvdb::Vec3d origin(10.0, -2.0, 1.0);
    auto grid = openvdb::FloatGrid::create(0.f);
    grid->setName("density");
    auto xf = openvdb::math::Transform::createLinearTransform(0.5);
    xf->postTranslate(origin);
    grid->setTransform(xf);
    auto value = [](int x, int y, int z) { return 1000.f + 100.f * x + 10.f * y + z; };
    for (int z = 3; z <= 4; ++z)
        for (int y = 0; y <= 2; ++y)
            for (int x = -2; x <= 1; ++x) grid->tree().setValue(openvdb::Coord(x, y, z), value(x, y, z));
    write_vdb(dir.path("g.vdb"), {grid});

    GridData data = read_vdb_file(dir.path("g.vdb"), "density");
    EXPECT_EQ(data.nx, 4);
    EXPECT_EQ(data.ny, 3);
    EXPECT_EQ(data.nz, 2);
    EXPECT_EQ(data.channels, 1);
    EXPECT_EQ(data.at(0, 0, 0), value(-2, 0, 3));
    EXPECT_EQ(data.at(3, 2, 1), value(1, 2, 4));
    // Cells: index [-2.5, 1.5] x [-0.5, 2.5] x [2.5, 4.5] through x -> 0.5 x + origin.
    EXPECT_FLOAT_EQ(data.bbox.lo.x, 10.f - 1.25f);
    EXPECT_FLOAT_EQ(data.bbox.hi.x, 10.f + 0.75f);
    EXPECT_FLOAT_EQ(data.bbox.lo.y, -2.25f);
    EXPECT_FLOAT_EQ(data.bbox.hi.y, -0.75f);
    EXPECT_FLOAT_EQ(data.bbox.lo.z, 2.25f);
    EXPECT_FLOAT_EQ(data.bbox.hi.z, 3.25f);

    // Through the volume: with use_grid_bbox each VDB voxel's world centre holds its value (nearest
    // and trilinear), then to_world applies on top.
    auto v = load_volume(dir, R"(<volume type="gridvolume"><string name="filename" value="g.vdb"/>
    <boolean name="use_grid_bbox" value="true"/><string name="filter_type" value="nearest"/></volume>
)");
    auto t = load_volume(dir, R"(<volume type="gridvolume"><string name="filename" value="g.vdb"/>
    <boolean name="use_grid_bbox" value="true"/>
    <transform name="to_world"><translate z="5"/></transform></volume>
)");
    ASSERT_TRUE(v);
    ASSERT_TRUE(t);
    for (int z = 3; z <= 4; ++z)
        for (int y = 0; y <= 2; ++y)
            for (int x = -2; x <= 1; ++x) {
                const Point3f c(float(origin.x() + 0.5 * x), float(origin.y() + 0.5 * y),
                                float(origin.z() + 0.5 * z));
                EXPECT_EQ(v->eval(c).r, value(x, y, z)) << x << " " << y << " " << z;
                EXPECT_NEAR(t->eval(c + Vec3f(0, 0, 5)).r, value(x, y, z), 0.05f)
                    << x << " " << y << " " << z;
            }
    EXPECT_NEAR(t->bbox().lo.z, 7.25f, 1e-5f);
    EXPECT_NEAR(t->bbox().hi.z, 8.25f, 1e-5f);
}

TEST(MediaVdb, InactiveVoxelsReadAsBackgroundAndVec3Grids) {
    ScratchDir dir;
    // Two active corner voxels; everything between is inactive and reads as the background 0.25.
    auto grid = openvdb::FloatGrid::create(0.25f);
    grid->setName("smoke");
    grid->tree().setValue(openvdb::Coord(0, 0, 0), 2.f);
    grid->tree().setValue(openvdb::Coord(3, 2, 1), 4.f);
    grid->tree().setValueOff(openvdb::Coord(1, 1, 1), 7.f);  // inactive with a stored value
    auto color = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.f));
    color->setName("albedo");
    for (int x = 0; x < 2; ++x)
        color->tree().setValue(openvdb::Coord(x, 0, 0), openvdb::Vec3s(0.1f * x, 0.2f, 0.3f));
    write_vdb(dir.path("two.vdb"), {grid, color});

    GridData d = read_vdb_file(dir.path("two.vdb"), "smoke");
    ASSERT_EQ(d.nx * d.ny * d.nz, 4 * 3 * 2);
    EXPECT_EQ(d.at(0, 0, 0), 2.f);
    EXPECT_EQ(d.at(3, 2, 1), 4.f);
    EXPECT_EQ(d.at(1, 1, 1), 0.25f);
    EXPECT_EQ(d.at(2, 0, 1), 0.25f);

    GridData c = read_vdb_file(dir.path("two.vdb"), "albedo");
    EXPECT_EQ(c.channels, 3);
    EXPECT_EQ(c.nx, 2);
    EXPECT_EQ(c.ny, 1);
    EXPECT_FLOAT_EQ(c.at(1, 0, 0, 0), 0.1f);
    EXPECT_FLOAT_EQ(c.at(1, 0, 0, 2), 0.3f);
    auto v = load_volume(dir, R"(<volume type="gridvolume"><string name="filename" value="two.vdb"/>
    <string name="grid" value="albedo"/><string name="filter_type" value="nearest"/></volume>
)");
    ASSERT_TRUE(v);
    EXPECT_NEAR(v->eval(Point3f(0.75f, 0.5f, 0.5f)).r, 0.1f, 1e-6f);
    EXPECT_NEAR(v->eval(Point3f(0.75f, 0.5f, 0.5f)).g, 0.2f, 1e-6f);
}

TEST(MediaVdb, NegativeScaleFlipsTheData) {
    ScratchDir dir;
    // x -> -x: index 0..3 at world x = 0, -1, -2, -3; the dense data runs along +x in world space.
    auto grid = openvdb::FloatGrid::create(0.f);
    grid->setName("density");
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    m(0, 0) = -1.0;
    grid->setTransform(openvdb::math::Transform::createLinearTransform(m));
    for (int x = 0; x < 4; ++x) grid->tree().setValue(openvdb::Coord(x, 0, 0), float(x + 1));
    write_vdb(dir.path("flip.vdb"), {grid});
    GridData d = read_vdb_file(dir.path("flip.vdb"), "density");
    ASSERT_EQ(d.nx, 4);
    EXPECT_EQ(d.at(0, 0, 0), 4.f);  // world x = -3
    EXPECT_EQ(d.at(3, 0, 0), 1.f);  // world x = 0
    EXPECT_FLOAT_EQ(d.bbox.lo.x, -3.5f);
    EXPECT_FLOAT_EQ(d.bbox.hi.x, 0.5f);
}

TEST(MediaVdb, BadFilesGridsAndTypesAreInputErrorsNamingTheFile) {
    ScratchDir dir;
    auto ramp = [](int x, int, int) { return float(x); };
    write_vdb(dir.path("two.vdb"),
              {float_grid("smoke", 2, 2, 2, openvdb::Vec3d(1.0), openvdb::Vec3d(0.0), ramp),
               float_grid("temperature", 2, 2, 2, openvdb::Vec3d(1.0), openvdb::Vec3d(0.0), ramp)});
    auto dgrid = openvdb::DoubleGrid::create(0.0);
    dgrid->setName("density");
    dgrid->tree().setValue(openvdb::Coord(0, 0, 0), 1.0);
    write_vdb(dir.path("double.vdb"), {dgrid});
    auto empty = openvdb::FloatGrid::create(0.f);
    empty->setName("density");
    write_vdb(dir.path("empty.vdb"), {empty});
    auto rotated = float_grid("density", 2, 2, 2, openvdb::Vec3d(1.0), openvdb::Vec3d(0.0), ramp);
    rotated->transform().postRotate(0.3, openvdb::math::Z_AXIS);
    write_vdb(dir.path("rotated.vdb"), {rotated});
    auto negative = float_grid("density", 2, 2, 2, openvdb::Vec3d(1.0), openvdb::Vec3d(0.0),
                               [](int, int, int) { return -1.f; });
    write_vdb(dir.path("negative.vdb"), {negative});
    dir.write("text.vdb", "hello, not a VDB file\n");
    std::filesystem::create_directories(dir.path("dir.vdb"));

    struct Case {
        const char* file;
        const char* grid;  // nullptr: the default "density"
        std::vector<std::string> needles;
    } cases[] = {
        {"missing.vdb", nullptr, {"not found"}},  // caught by the loader's file lookup
        {"text.vdb", nullptr, {"cannot read"}},
        {"dir.vdb", nullptr, {"directory"}},
        {"two.vdb", nullptr, {"\"density\"", "\"smoke\"", "\"temperature\""}},
        {"two.vdb", "fog", {"\"fog\"", "\"smoke\", \"temperature\""}},
        {"double.vdb", nullptr, {"double", "unsupported type"}},
        {"empty.vdb", nullptr, {"empty"}},
        {"rotated.vdb", nullptr, {"rotated"}},
        {"negative.vdb", nullptr, {"invalid value -1"}},
    };
    for (const Case& c : cases) {
        std::string grid = c.grid ? std::string("<string name=\"grid\" value=\"") + c.grid + "\"/>" : "";
        std::string xml =
            dir.write("e.xml", scene(std::string("<volume type=\"gridvolume\">\n<string name=\"filename\" "
                                                 "value=\"") +
                                     c.file + "\"/>" + grid + "\n</volume>\n"));
        for (const std::string& needle : c.needles)
            expect_input_error([&] { load_scene_properties(xml); }, xml, 3, needle);
        try {
            load_scene_properties(xml);
            ADD_FAILURE() << c.file;
        } catch (const InputError& e) {
            EXPECT_NE(e.message().find(c.file), std::string::npos) << e.what();
        }
    }
    // The reader itself: InputErrors located at the file, naming it.
    for (const char* file : {"two.vdb", "missing.vdb"}) {
        try {
            read_vdb_file(dir.path(file), "fog");
            ADD_FAILURE() << file;
        } catch (const InputError& e) {
            EXPECT_EQ(e.location().file, dir.path(file));
            EXPECT_NE(e.message().find(file), std::string::npos) << e.what();
        }
    }
    try {
        read_vdb_file(dir.path("missing.vdb"), "density");
    } catch (const InputError& e) {
        EXPECT_NE(e.message().find("cannot open"), std::string::npos) << e.what();
    }
    // 'grid' is only for .vdb files.
    VolGrid g = make_vol_grid(2, 2, 2, 1, [](float, float, float, int) { return 1.f; });
    write_vol_file(dir.path("a.vol"), g);
    std::string xml =
        dir.write("g.xml", scene("<volume type=\"gridvolume\">\n<string name=\"filename\" "
                                 "value=\"a.vol\"/>\n<string name=\"grid\" value=\"x\"/>\n</volume>\n"));
    expect_input_error([&] { load_scene_properties(xml); }, xml, 4, "grid");
}

// check_vdb_header holds a table of the sizes OpenVDB reads for its fixed-size metadata types,
// whatever size the file declares (a wrong entry rejects good files or lets a reader fall out of step).
// Every type OpenVDB 10 registers is compared with the library's own size; the names come from
// openvdb::initialize() (metadata, point index and point data index types, delayed-load metadata).
TEST(MediaVdb, MetadataLayoutTableMatchesOpenVdb) {
    openvdb::initialize();
    const char* fixed[] = {"bool",  "int32", "int64", "float", "double", "vec2i",   "vec2s",
                           "vec2d", "vec3i", "vec3s", "vec3d", "vec4i",  "vec4s",   "vec4d",
                           "mat4s", "mat4d", "ptidx32", "ptidx64", "ptdataidx32", "ptdataidx64"};
    for (const char* type : fixed) {
        SCOPED_TRACE(type);
        ASSERT_TRUE(openvdb::Metadata::isRegisteredType(type));
        ASSERT_TRUE(vdb_metadata_layout_bytes(type).has_value());
        EXPECT_EQ(*vdb_metadata_layout_bytes(type), openvdb::Metadata::createMetadata(type)->size());
    }
    // Read by their declared size: strings, delayed-load metadata (walked separately) and types
    // OpenVDB does not register (kept as UnknownMetadata).
    for (const char* type : {"string", "__delayedload", "mat3s", "uint32", "half"}) {
        SCOPED_TRACE(type);
        EXPECT_FALSE(vdb_metadata_layout_bytes(type).has_value());
        if (std::string(type) == "string" || std::string(type) == "__delayedload")
            EXPECT_TRUE(openvdb::Metadata::isRegisteredType(type));
        else
            EXPECT_FALSE(openvdb::Metadata::isRegisteredType(type));
    }
}

// What OpenVDB writes passes the header check: grid metadata of every registered type and the
// delayed-load metadata io::File adds, with its leaf mask and compressed sizes Blosc-compressed
// (a grid of 1000 leaves: the arrays compress).
TEST(MediaVdb, FilesWithMetadataOfEveryTypeAndBloscDelayedLoadPassTheHeaderCheck) {
    ScratchDir dir;
    auto grid = float_grid("density", 80, 80, 80, openvdb::Vec3d(0.1), openvdb::Vec3d(0.0),
                           [](int x, int y, int z) { return float((x + y + z) % 7); });
    ASSERT_EQ(grid->tree().leafCount(), 1000u);
    grid->insertMeta("b", openvdb::BoolMetadata(true));
    grid->insertMeta("i", openvdb::Int32Metadata(3));
    grid->insertMeta("l", openvdb::Int64Metadata(4));
    grid->insertMeta("f", openvdb::FloatMetadata(5.f));
    grid->insertMeta("d", openvdb::DoubleMetadata(6.0));
    grid->insertMeta("s", openvdb::StringMetadata("a string"));
    grid->insertMeta("v2i", openvdb::Vec2IMetadata(openvdb::Vec2i(1, 2)));
    grid->insertMeta("v2s", openvdb::Vec2SMetadata(openvdb::Vec2s(1, 2)));
    grid->insertMeta("v2d", openvdb::Vec2DMetadata(openvdb::Vec2d(1, 2)));
    grid->insertMeta("v3i", openvdb::Vec3IMetadata(openvdb::Vec3i(1, 2, 3)));
    grid->insertMeta("v3s", openvdb::Vec3SMetadata(openvdb::Vec3s(1, 2, 3)));
    grid->insertMeta("v3d", openvdb::Vec3DMetadata(openvdb::Vec3d(1, 2, 3)));
    grid->insertMeta("v4i", openvdb::Vec4IMetadata(openvdb::Vec4i(1, 2, 3, 4)));
    grid->insertMeta("v4s", openvdb::Vec4SMetadata(openvdb::Vec4s(1, 2, 3, 4)));
    grid->insertMeta("v4d", openvdb::Vec4DMetadata(openvdb::Vec4d(1, 2, 3, 4)));
    grid->insertMeta("m4s", openvdb::Mat4SMetadata(openvdb::math::Mat4s::identity()));
    grid->insertMeta("m4d", openvdb::Mat4DMetadata(openvdb::math::Mat4d::identity()));
    const std::string path = dir.path("meta.vdb");
    write_vdb(path, {grid});
    const std::string bytes = file_bytes(path);
    // io::File wrote the delayed-load metadata, and Blosc compressed the mask (its 1000 bytes are not
    // stored raw: the byte count after the leaf count is not 0).
    const size_t type = bytes.find("__delayedload");
    ASSERT_NE(type, std::string::npos);
    uint32_t size = 0, count = 0, mask_bytes = 0;
    std::memcpy(&size, &bytes[type + 13], 4);
    std::memcpy(&count, &bytes[type + 17], 4);
    std::memcpy(&mask_bytes, &bytes[type + 21], 4);
    EXPECT_EQ(count, 1000u);
    EXPECT_GT(mask_bytes, 0u);
    EXPECT_LT(size, 1000u);
    EXPECT_NO_THROW(check_vdb_header(path));
    EXPECT_EQ(read_vdb_file(path, "density").nx, 80);
    // The same file with the mask's Blosc header declaring 2^30 uncompressed bytes (OpenVDB reserves
    // them) is refused.
    std::string bad = bytes;
    const uint32_t huge = 1u << 30;
    std::memcpy(&bad[type + 25 + 4], &huge, 4);
    const std::string bad_path = dir.write("bad.vdb", bad);
    try {
        check_vdb_header(bad_path);
        ADD_FAILURE() << "accepted a Blosc header declaring 2^30 bytes";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("leaf mask's Blosc header declares 1073741824 bytes"), std::string::npos)
            << e.what();
    }
}

// Densifying writes the background once and then each active voxel and tile (tile rows are copied,
// not probed voxel by voxel). Every dense voxel must equal what an accessor reads there (the
// background where inactive), for float and vec3 grids, tiles clipped by the active box, and axes
// flipped by negative scales.
TEST(MediaVdb, DenseValuesMatchEveryVoxelOfTilesAndVoxels) {
    ScratchDir dir;
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    m(0, 0) = -1.0;
    m(2, 2) = -0.5;
    auto density = openvdb::FloatGrid::create(0.25f);
    density->setName("density");
    density->setTransform(openvdb::math::Transform::createLinearTransform(m));
    density->tree().addTile(1, openvdb::Coord(8, 0, 0), 3.f, true);     // an active 8^3 tile
    density->tree().addTile(1, openvdb::Coord(0, 8, 0), 5.f, false);    // an inactive one
    density->tree().setValue(openvdb::Coord(2, 3, 4), 7.f);
    density->tree().setValue(openvdb::Coord(21, 1, 9), 9.f);            // beyond the tiles
    density->tree().setValueOff(openvdb::Coord(1, 1, 1), 11.f);
    auto color = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.1f, 0.2f, 0.3f));
    color->setName("albedo");
    color->setTransform(openvdb::math::Transform::createLinearTransform(m));
    color->tree().addTile(1, openvdb::Coord(0, 0, 8), openvdb::Vec3s(1.f, 2.f, 3.f), true);
    color->tree().setValue(openvdb::Coord(9, 2, 3), openvdb::Vec3s(4.f, 5.f, 6.f));
    write_vdb(dir.path("tiles.vdb"), {density, color});

    auto check = [&](const auto& grid, int channels) {
        SCOPED_TRACE(grid->getName());
        const GridData d = read_vdb_file(dir.path("tiles.vdb"), grid->getName());
        const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
        ASSERT_EQ(d.channels, channels);
        ASSERT_EQ(d.nx, box.dim().x());
        ASSERT_EQ(d.ny, box.dim().y());
        ASSERT_EQ(d.nz, box.dim().z());
        auto acc = grid->getConstAccessor();
        int mismatches = 0;
        for (int z = 0; z < d.nz; ++z)
            for (int y = 0; y < d.ny; ++y)
                for (int x = 0; x < d.nx; ++x) {
                    const openvdb::Coord c = box.min() + openvdb::Coord(x, y, z);
                    const auto v = acc.isValueOn(c) ? acc.getValue(c) : grid->background();
                    // x and z are flipped (negative scales): dense index nx - 1 - x, nz - 1 - z.
                    for (int ch = 0; ch < channels; ++ch) {
                        float want;
                        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, float>)
                            want = v;
                        else
                            want = v[ch];
                        if (d.at(d.nx - 1 - x, y, d.nz - 1 - z, ch) != want && ++mismatches <= 5)
                            ADD_FAILURE() << "voxel " << c << " channel " << ch << ": "
                                          << d.at(d.nx - 1 - x, y, d.nz - 1 - z, ch) << ", expected " << want;
                    }
                }
        EXPECT_EQ(mismatches, 0);
    };
    check(density, 1);
    check(color, 3);
    // The active box spans the voxel at x = 2, the active tile and the voxel at x = 21 (the inactive
    // tile is outside it): 20 x 8 x 10.
    const GridData d = read_vdb_file(dir.path("tiles.vdb"), "density");
    EXPECT_EQ(d.nx * 100 + d.ny * 10 + d.nz, 20 * 100 + 8 * 10 + 10);
}

// The header check steps over each grid's transform by its map type's layout and then bounds the
// root node's tile and child counts (a fuzzed 10 KB file declared 1.7 G root children, each a
// 264 KiB node OpenVDB allocates before reading it). Files OpenVDB writes with every map type
// volguide reads, for every value size of the registered tree types, must pass; a frustum map is
// refused (volguide reads scale and translation only).
TEST(MediaVdb, HeaderCheckStepsOverEveryMapTypeToTheRootNode) {
    ScratchDir dir;
    namespace m = openvdb::math;
    const std::vector<std::pair<std::string, m::MapBase::Ptr>> maps = {
        {"AffineMap", m::MapBase::Ptr(new m::AffineMap(m::Mat4d::identity()))},
        {"UnitaryMap", m::MapBase::Ptr(new m::UnitaryMap(openvdb::Vec3d(0, 0, 1), 0.3))},
        {"ScaleMap", m::MapBase::Ptr(new m::ScaleMap(openvdb::Vec3d(1, 2, 3)))},
        {"UniformScaleMap", m::MapBase::Ptr(new m::UniformScaleMap(0.5))},
        {"TranslationMap", m::MapBase::Ptr(new m::TranslationMap(openvdb::Vec3d(1, 2, 3)))},
        {"ScaleTranslateMap",
         m::MapBase::Ptr(new m::ScaleTranslateMap(openvdb::Vec3d(1, 2, 3), openvdb::Vec3d(4, 5, 6)))},
        {"UniformScaleTranslateMap",
         m::MapBase::Ptr(new m::UniformScaleTranslateMap(0.5, openvdb::Vec3d(4, 5, 6)))},
    };
    for (const auto& [type, map] : maps) {
        SCOPED_TRACE(type);
        ASSERT_EQ(map->type(), type);
        openvdb::GridPtrVec grids;
        // map captured by an init-capture: clang 14 cannot capture a structured binding (C++20's P1091).
        auto add = [&, &map = map](openvdb::GridBase::Ptr grid, const std::string& name) {
            grid->setName(name);
            grid->setTransform(openvdb::math::Transform::Ptr(new openvdb::math::Transform(map->copy())));
            grids.push_back(grid);
        };
        auto f = openvdb::FloatGrid::create(0.5f);
        f->tree().setValue(openvdb::Coord(1, 2, 3), 1.f);
        f->tree().addTile(3, openvdb::Coord(8192, 0, 0), 2.f, false);  // an (inactive) root tile
        add(f, "density");
        auto v = openvdb::Vec3SGrid::create(openvdb::Vec3s(1.f));
        v->tree().setValue(openvdb::Coord(-100, 5000, 3), openvdb::Vec3s(2.f));
        add(v, "albedo");
        auto d = openvdb::Vec3DGrid::create();
        d->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3d(2.0));
        add(d, "vec3d");
        auto b = openvdb::BoolGrid::create();
        b->tree().setValue(openvdb::Coord(0, 0, 0), true);
        add(b, "bool");
        auto half = openvdb::FloatGrid::create(0.f);
        half->tree().setValue(openvdb::Coord(7, 7, 7), 3.f);
        half->setSaveFloatAsHalf(true);
        add(half, "half");
        const std::string path = dir.path(type + ".vdb");
        write_vdb(path, grids);
        EXPECT_NO_THROW(check_vdb_header(path));
        if (type == "UnitaryMap") continue;  // a rotation: read_vdb_file refuses it after the check
        EXPECT_EQ(read_vdb_file(path, "density").channels, 1);
        EXPECT_EQ(read_vdb_file(path, "albedo").channels, 3);
    }
    auto frustum = openvdb::FloatGrid::create();
    frustum->setName("density");
    frustum->tree().setValue(openvdb::Coord(0, 0, 0), 1.f);
    frustum->setTransform(openvdb::math::Transform::createFrustumTransform(
        openvdb::BBoxd(openvdb::Vec3d(0), openvdb::Vec3d(10)), 0.5, 2.0, 1.0));
    write_vdb(dir.path("frustum.vdb"), {frustum});
    try {
        check_vdb_header(dir.path("frustum.vdb"));
        ADD_FAILURE() << "accepted a frustum transform";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("\"NonlinearFrustumMap\" transform"), std::string::npos) << e.what();
    }
}

// The header check walks every tree to its last voxel buffer and requires it to end where the grid's
// descriptor says (its topology at the block offset, its buffers at the end offset): a walk that
// misreads any node's layout fails here. Grids of every walked tree type, each compression OpenVDB
// writes, half floats, tiles at every level, leaves with each kind of inactive values (background,
// -background, one and two other values), several root children, in one file; the float and vec3s
// grids must still read as OpenVDB holds them.
TEST(MediaVdb, HeaderCheckWalksEveryTreeToTheEndTheDescriptorsGive) {
    openvdb::initialize();
    ScratchDir dir;
    auto fill = [](auto& grid, auto value, auto other, auto minus) {
        auto acc = grid.getAccessor();
        for (int z = 0; z < 12; ++z)
            for (int y = 0; y < 12; ++y)
                for (int x = 0; x < 12; ++x) acc.setValue(openvdb::Coord(x, y, z), value);
        // Inactive non-background values: one other value in one leaf, two in another, -background.
        acc.setValueOff(openvdb::Coord(1, 1, 1), other);
        acc.setValueOff(openvdb::Coord(9, 9, 9), other);
        acc.setValueOff(openvdb::Coord(10, 9, 9), minus);
        acc.setValueOff(openvdb::Coord(1, 9, 1), minus);
        // A far root child (negative coordinates) and tiles at the leaf, 16^3 and 32^3 levels.
        acc.setValue(openvdb::Coord(-5000, 7, -3), value);
        grid.tree().addTile(1, openvdb::Coord(128, 0, 0), value, true);
        grid.tree().addTile(2, openvdb::Coord(4096, 0, 0), value, true);
        grid.tree().addTile(3, openvdb::Coord(0, 0, 8192), other, false);
    };
    const uint32_t compressions[] = {openvdb::io::COMPRESS_NONE,
                                     openvdb::io::COMPRESS_ZIP,
                                     openvdb::io::COMPRESS_ACTIVE_MASK,
                                     openvdb::io::COMPRESS_BLOSC,
                                     openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK,
                                     openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK};
    for (const uint32_t compression : compressions)
        for (const bool half : {false, true}) {
            SCOPED_TRACE(::testing::Message() << "compression " << compression << ", half " << half);
            auto density = openvdb::FloatGrid::create(0.5f);
            density->setName("density");
            fill(*density, 2.f, 3.f, -0.5f);
            density->setSaveFloatAsHalf(half);
            auto albedo = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.5f));
            albedo->setName("albedo");
            fill(*albedo, openvdb::Vec3s(1, 2, 3), openvdb::Vec3s(4, 5, 6), openvdb::Vec3s(-0.5f));
            albedo->setSaveFloatAsHalf(half);
            auto d = openvdb::DoubleGrid::create(1.0);
            d->setName("double");
            fill(*d, 2.0, 3.0, -1.0);
            d->setSaveFloatAsHalf(half);
            auto i = openvdb::Int32Grid::create(1);
            i->setName("int");
            fill(*i, 2, 3, -1);
            auto v = openvdb::Vec3DGrid::create(openvdb::Vec3d(1.0));
            v->setName("vec3d");
            fill(*v, openvdb::Vec3d(2.0), openvdb::Vec3d(3.0), openvdb::Vec3d(-1.0));
            auto b = openvdb::BoolGrid::create(false);
            b->setName("bool");
            fill(*b, true, true, false);
            auto m = openvdb::MaskGrid::create(false);
            m->setName("mask");
            m->topologyUnion(*density);
            auto empty = openvdb::FloatGrid::create(0.f);
            empty->setName("empty");
            // Small grids to read (the ones above span 13000 voxels).
            auto small = float_grid("small", 3, 2, 2, openvdb::Vec3d(1.0), openvdb::Vec3d(0.0),
                                    [](int x, int, int) { return float(x); });
            small->setSaveFloatAsHalf(half);
            auto small_albedo = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.f));
            small_albedo->setName("small_albedo");
            small_albedo->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1, 2, 3));
            small_albedo->setSaveFloatAsHalf(half);
            const std::string path = dir.path("grids.vdb");
            openvdb::io::File file(path);
            file.setCompression(compression);
            file.write({density, albedo, d, i, v, b, m, empty, small, small_albedo});
            file.close();
            EXPECT_NO_THROW(check_vdb_header(path));
            const GridData g = read_vdb_file(path, "small");
            ASSERT_EQ(g.nx, 3);
            EXPECT_EQ(g.at(2, 1, 1), 2.f);
            const GridData a = read_vdb_file(path, "small_albedo");
            ASSERT_EQ(a.channels, 3);
            EXPECT_EQ(a.at(0, 0, 0, 2), 3.f);
            // One byte more or less anywhere in a tree puts its end elsewhere: cut the file short.
            const std::string bytes = file_bytes(path);
            EXPECT_THROW(check_vdb_header(dir.write("short.vdb", bytes.substr(0, bytes.size() - 1))), InputError);
        }
}

// A 32^3 node whose child mask says every child is there: OpenVDB would allocate 32768 16^3 nodes
// (1.1 GB) from a small file, reading on after the stream ran dry. The walk needs each child's masks
// in the file.
TEST(MediaVdb, HeaderCheckRefusesInternalNodesTheFileCannotHold) {
    ScratchDir dir;
    auto grid = float_grid("density", 2, 2, 2, openvdb::Vec3d(1.0), openvdb::Vec3d(0.0),
                           [](int, int, int) { return 1.f; });
    const std::string path = dir.path("one.vdb");
    openvdb::io::File file(path);
    file.setCompression(openvdb::io::COMPRESS_NONE);
    file.write({grid});
    file.close();
    std::string bytes = file_bytes(path);
    // The root's one child: its origin, then its 4096-byte child mask, whose first word is bit 0.
    const size_t type = bytes.find("UniformScale");
    ASSERT_NE(type, std::string::npos);
    const bool translate = bytes.compare(type, 24, "UniformScaleTranslateMap") == 0;
    const size_t map_end = translate ? type + 24 + 6 * 24 : type + 15 + 5 * 24;
    const size_t children_at = map_end + 4 + 4 + 4;  // buffer count, background, tile count
    uint32_t children = 0;
    std::memcpy(&children, &bytes[children_at], 4);
    ASSERT_EQ(children, 1u);
    const size_t mask_at = children_at + 4 + 12;
    uint64_t first = 0;
    std::memcpy(&first, &bytes[mask_at], 8);
    ASSERT_EQ(first, 1u);
    std::memset(&bytes[mask_at], 0xff, 4096);
    const std::string bad = dir.write("full.vdb", bytes);
    try {
        read_vdb_file(bad, "density");
        ADD_FAILURE() << "accepted a full child mask";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("runs past the end of the file"), std::string::npos) << e.what();
    }
}

// A scale map stores its scale and the values derived from it, and OpenVDB reads them all: a fuzzed
// file whose voxel size said 0.5 while its scale was nearly zero made getAffineMap() throw past a frame
// that cannot unwind (std::terminate). The header check refuses stored values that disagree; the
// reader takes the matrix from where the map sends the unit vectors, not from getAffineMap().
TEST(MediaVdb, ScaleMapsWhoseStoredValuesDisagreeAreRefused) {
    ScratchDir dir;
    auto grid = float_grid("density", 2, 2, 2, openvdb::Vec3d(0.5), openvdb::Vec3d(0.0),
                           [](int, int, int) { return 1.f; });
    const std::string path = dir.path("good.vdb");
    write_vdb(path, {grid});
    EXPECT_EQ(read_vdb_file(path, "density").nx, 2);
    std::string bytes = file_bytes(path);
    const size_t type = bytes.find("UniformScaleMap");
    ASSERT_NE(type, std::string::npos);
    double scale = 0.0;
    std::memcpy(&scale, &bytes[type + 15], 8);
    ASSERT_EQ(scale, 0.5);
    const double tiny = 1e-300;
    std::memcpy(&bytes[type + 15], &tiny, 8);
    const std::string bad = dir.write("bad.vdb", bytes);
    try {
        read_vdb_file(bad, "density");
        ADD_FAILURE() << "accepted a scale map storing scale 1e-300 and voxel size 0.5";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("(inconsistent)"), std::string::npos) << e.what();
    }
}
