// Resources are bounded before allocation (issue 24): sizes read from a file are checked against the
// file's size or the machine's memory, and each violation is an InputError naming the file (and the
// line, for scenes). Each case here allocated or recursed without bound before its check existed.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "support/cli.h"
#include "test_loader_util.h"
#include "volguide/core/memory.h"
#include "volguide/geometry/shapes/mesh_files.h"
#include "volguide/media/grid_data.h"
#include "volguide/render/image_io.h"
#include "volguide/render/sensors/hdrfilm.h"
#include "volguide/scene/xml_file.h"

using namespace volguide;
using namespace volguide::test;

namespace {

// A .vol header declaring nx x ny x nz x channels floats, followed by `data_floats` floats.
std::string vol_bytes(int32_t nx, int32_t ny, int32_t nz, int32_t channels, int data_floats) {
    std::string b = "VOL";
    b += char(3);
    const int32_t ints[5] = {1, nx, ny, nz, channels};
    const float box[6] = {0, 0, 0, 1, 1, 1};
    b.append(reinterpret_cast<const char*>(ints), sizeof(ints));
    b.append(reinterpret_cast<const char*>(box), sizeof(box));
    b.append(size_t(4 * data_floats), '\0');
    return b;
}

template <typename F>
void expect_error_containing(F&& f, const std::string& needle) {
    try {
        f();
        ADD_FAILURE() << "accepted; expected an InputError containing \"" << needle << "\"";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(ResourceLimits, VolResolutionIsBoundedByTheFileSizeWithoutOverflow) {
    ScratchDir dir;
    // 2^21 cubed is 2^63 floats: 4 bytes each wraps a 64-bit byte count to 0, which once passed the
    // size check and asked for 2^63 values.
    const std::string wraps = dir.write("wrap.vol", vol_bytes(1 << 21, 1 << 21, 1 << 21, 1, 3));
    expect_error_containing([&] { read_vol_file(wraps); }, "truncated .vol data");
    expect_error_containing([&] { read_vol_file(wraps); }, "wrap.vol");
    const std::string large = dir.write("large.vol", vol_bytes(1 << 30, 1 << 30, 2, 3, 3));
    expect_error_containing([&] { read_vol_file(large); }, "truncated .vol data");
    // The bound is exact: the declared floats, no more, are enough.
    const std::string exact = dir.write("exact.vol", vol_bytes(2, 3, 1, 3, 18));
    EXPECT_EQ(read_vol_file(exact).values.size(), 18u);
}

TEST(ResourceLimits, PlyElementCountsAreBoundedByTheFileSize) {
    ScratchDir dir;
    const SourceLocation loc{"scene.xml", 7};
    const std::string huge = dir.write("huge.ply",
                                       "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
                                       "property float x\nproperty float y\nproperty float z\n"
                                       "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                       "0123456789");
    try {
        read_ply(huge, loc);
        ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.location().line, 7);
        EXPECT_NE(e.message().find("huge.ply"), std::string::npos) << e.what();
        EXPECT_NE(e.message().find("declares 1000000000000 entries but only 10 bytes"), std::string::npos)
            << e.what();
    }
}

TEST(ResourceLimits, PlyListLengthsMustBeNonNegativeIntegersThatFit) {
    ScratchDir dir;
    const std::string header =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list float int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    for (const char* count : {"-1", "2.5", "nan", "1e30"}) {
        const std::string path = dir.write("list.ply", header + count + " 0 1 2\n");
        SCOPED_TRACE(count);
        expect_error_containing([&] { read_ply(path, SourceLocation{"s.xml", 1}); },
                                "invalid length");
    }
}

TEST(ResourceLimits, XmlNestingDepthIsBounded) {
    ScratchDir dir;
    std::string body;
    for (int i = 0; i < kMaxXmlDepth + 5; ++i) body += "<shape type=\"sphere\">\n";
    for (int i = 0; i < kMaxXmlDepth + 5; ++i) body += "</shape>\n";
    const std::string path = dir.write("deep.xml", scene(body));
    // Line 1 is <scene>, so the first element below the limit is on line kMaxXmlDepth + 1.
    expect_input_error([&] { load_fake(path); }, path, kMaxXmlDepth + 1, "nested more than 64 levels");
    // At the limit exactly, the depth check passes (the scene is then read as usual).
    std::string ok;
    for (int i = 0; i < kMaxXmlDepth - 1; ++i) ok += "<shape type=\"sphere\">\n";
    for (int i = 0; i < kMaxXmlDepth - 1; ++i) ok += "</shape>\n";
    EXPECT_NO_THROW(load_fake(dir.write("ok.xml", scene(ok))));
}

TEST(ResourceLimits, IncludeDepthIsBounded) {
    ScratchDir dir;
    // inc0 includes inc1 ... which includes inc40: acyclic, but deeper than 32 files.
    const int n = 40;
    for (int i = 0; i < n; ++i)
        dir.write("inc" + std::to_string(i) + ".xml",
                  scene("<include filename=\"inc" + std::to_string(i + 1) + ".xml\"/>\n"));
    dir.write("inc" + std::to_string(n) + ".xml", scene(""));
    // The main file is the first level; the 32nd file's include (line 2) is refused.
    expect_input_error([&] { load_fake(dir.path("inc0.xml")); }, dir.path("inc31.xml"), 2,
                       "includes nested more than 32 files");
    EXPECT_NO_THROW(load_fake(dir.path(("inc" + std::to_string(n - 30) + ".xml"))));
}

namespace {

// A scene whose film is n x n pixels (the film's element on line 4 of the file).
std::string film_scene(int n) {
    return scene(fmt::format(R"(<sensor type="perspective">
<film type="hdrfilm">
<integer name="width" value="{0}"/>
<integer name="height" value="{0}"/>
</film>
</sensor>
)",
                             n));
}

}  // namespace

TEST(ResourceLimits, FilmSizeIsBoundedByTheMachinesMemory) {
    const uint64_t need = film_memory_bytes(65536, 65536);
    if (memory_budget_bytes() >= need) GTEST_SKIP() << "this machine could hold a 65536^2 film";
    ScratchDir dir;
    const std::string path = dir.write("film.xml", film_scene(65536));
    expect_input_error([&] { load_scene_properties(path); }, path, 4, "film needs about 512.0 GiB of memory");
}

TEST(ResourceLimits, MemoryBudgetFollowsTheEnvironment) {
    ScratchDir dir;
    const std::string path = dir.write("film.xml", film_scene(4096));
    // 4096^2 pixels need 2 GiB: refused under a 1 GiB budget, with the budget named.
    setenv("VOLGUIDE_MEMORY_LIMIT_MB", "1024", 1);
    EXPECT_EQ(memory_budget_bytes(), std::min<uint64_t>(physical_memory_bytes(), uint64_t(1) << 30));
    expect_input_error([&] { load_scene_properties(path); }, path, 4,
                       "needs about 2.0 GiB of memory, more than the VOLGUIDE_MEMORY_LIMIT_MB budget of 1.0 GiB");
    setenv("VOLGUIDE_MEMORY_LIMIT_MB", "lots", 1);
    EXPECT_THROW(memory_budget_bytes(), std::invalid_argument);
    unsetenv("VOLGUIDE_MEMORY_LIMIT_MB");
    EXPECT_EQ(memory_budget_bytes(), physical_memory_bytes());
}

TEST(ResourceLimits, FilmMemoryEstimate) {
    EXPECT_EQ(film_memory_bytes(1920, 1080), 1920u * 1080u * kFilmBytesPerPixel);
    EXPECT_EQ(format_bytes(512), "512 B");
    EXPECT_EQ(format_bytes(3u << 20), "3.0 MiB");
}

TEST(ResourceLimits, VdbMetadataLengthsAreBoundedByTheFileSize) {
    // The seed of the vdb fuzzer with its grid's first metadata name declared 2^31 - 1 bytes long
    // (grid offset 0x7c, then uint32 compression and uint32 entry count): OpenVDB would allocate
    // that string before reading it.
    std::ifstream in(std::string(VOLGUIDE_SOURCE_DIR) + "/tests/fuzz/corpus/vdb/density_2x2x2.vdb", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 0x88u);
    ScratchDir dir;
    const std::string valid = dir.write("valid.vdb", bytes);
    EXPECT_EQ(read_vdb_file(valid, "density").nx, 2);
    const int32_t huge = 0x7fffffff;
    std::memcpy(&bytes[0x84], &huge, 4);
    std::ofstream(dir.path("long.vdb"), std::ios::binary) << bytes;
    expect_error_containing([&] { read_vdb_file(dir.path("long.vdb"), "density"); },
                            "metadata name (2147483647 bytes at offset 136) runs past the end of the file");
}

TEST(ResourceLimits, VdbFixedSizeMetadataMustDeclareItsLayoutsSize) {
    // A fuzzer's input (tests/fuzz/regression/vdb): the seed with "file_bbox_max" typed "vec4i" but
    // still declaring 12 bytes. OpenVDB reads a vec4i's 16, takes the next length from the bytes of
    // the next name ("file" = 1.7 G) and allocated a 1.7 GB string.
    const std::string input =
        std::string(VOLGUIDE_SOURCE_DIR) + "/tests/fuzz/regression/vdb/oom-metamap-string-1.7gb.vdb";
    expect_error_containing([&] { read_vdb_file(input, "density"); },
                            "a \"vec4i\" metadata value declares 12 bytes; OpenVDB reads 16");
    expect_error_containing([&] { read_vdb_file(input, "density"); }, "oom-metamap-string-1.7gb.vdb");
}

TEST(ResourceLimits, VdbDelayedLoadMetadataIsBoundedByItsValueAndTheFile) {
    // The seed's delayed-load metadata: declared size 13 = leaf count 1, mask byte count 0 (raw),
    // one mask byte, compressed-size byte count 0xffffffff (none stored).
    std::ifstream in(std::string(VOLGUIDE_SOURCE_DIR) + "/tests/fuzz/corpus/vdb/density_2x2x2.vdb", std::ios::binary);
    const std::string seed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t type = seed.find("__delayedload");
    ASSERT_NE(type, std::string::npos);
    const size_t size_at = type + 13, count_at = size_at + 4, mask_bytes_at = count_at + 4;
    uint32_t size = 0;
    std::memcpy(&size, &seed[size_at], 4);
    ASSERT_EQ(size, 13u);
    ScratchDir dir;
    EXPECT_EQ(read_vdb_file(dir.write("valid.vdb", seed), "density").nx, 2);
    auto with = [&](size_t at, uint32_t value, const char* name) {
        std::string bytes = seed;
        std::memcpy(&bytes[at], &value, 4);
        return dir.write(name, bytes);
    };
    // OpenVDB sizes the leaf mask by the count before reading it: 2^31 leaves cannot be in 10 KB.
    expect_error_containing([&] { read_vdb_file(with(count_at, 0x7fffffff, "count.vdb"), "density"); },
                            "delayed-load metadata for 2147483647 leaves in a file of");
    // 100 raw mask bytes do not fit in the 13-byte value (OpenVDB would read past it, out of step).
    expect_error_containing([&] { read_vdb_file(with(count_at, 100, "mask.vdb"), "density"); },
                            "the delayed-load leaf mask (100 bytes at offset");
    // A compressed mask of 6 bytes does not fit in the 5 left of the value.
    expect_error_containing([&] { read_vdb_file(with(mask_bytes_at, 6, "blosc.vdb"), "density"); },
                            "the delayed-load leaf mask (6 bytes at offset");
    // A 1-byte "Blosc buffer" is shorter than Blosc's header, which OpenVDB reads for the sizes.
    expect_error_containing([&] { read_vdb_file(with(mask_bytes_at, 1, "blosc1.vdb"), "density"); },
                            "is a 1-byte Blosc buffer");
}

TEST(ResourceLimits, VdbRootNodeCountsAreBoundedByTheFile) {
    // The seed: grid transform "UniformScaleMap" (120 bytes) ends at offset 566, then the buffer
    // count 1, the background, 0 tiles and 1 child. OpenVDB allocates each declared child (264 KiB)
    // before reading it; a fuzzed file declared 1.7 G of them.
    std::ifstream in(std::string(VOLGUIDE_SOURCE_DIR) + "/tests/fuzz/corpus/vdb/density_2x2x2.vdb", std::ios::binary);
    const std::string seed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_EQ(seed.compare(431, 15, "UniformScaleMap"), 0);
    const size_t buffers_at = 566, tiles_at = 574, children_at = 578;
    uint32_t v[4];
    std::memcpy(v, &seed[buffers_at], 16);
    ASSERT_EQ(v[0], 1u);
    ASSERT_EQ(v[2], 0u);
    ASSERT_EQ(v[3], 1u);
    ScratchDir dir;
    auto with = [&](size_t at, uint32_t value, const char* name) {
        std::string bytes = seed;
        std::memcpy(&bytes[at], &value, 4);
        return dir.write(name, bytes);
    };
    EXPECT_EQ(read_vdb_file(with(children_at, 1, "valid.vdb"), "density").nx, 2);
    expect_error_containing([&] { read_vdb_file(with(children_at, 1702232064, "children.vdb"), "density"); },
                            "the tree's root declares 1702232064 child nodes");
    // One child needs 8 KiB of masks: the 10 KB seed cannot hold two.
    expect_error_containing([&] { read_vdb_file(with(children_at, 2, "two.vdb"), "density"); },
                            "the tree's root declares 2 child nodes (at least 8204 bytes each)");
    expect_error_containing([&] { read_vdb_file(with(tiles_at, 358497, "tiles.vdb"), "density"); },
                            "the tree's root declares 358497 tiles of 17 bytes");
    expect_error_containing([&] { read_vdb_file(with(buffers_at, 2, "buffers.vdb"), "density"); },
                            "a tree declares 2 buffers");
}

// A texture's image (read_image of PNG, JPEG, BMP, TGA) is bounded before its decoder allocates: a
// 678-byte JPEG declaring 8000 x 8000 pixels made stb_image allocate about 1 GB and decode for 9 s;
// pixels are now bounded by the file's size, and the decode buffers by the memory budget.
TEST(ResourceLimits, ImageSizeIsBoundedByTheFileSizeAndTheBudget) {
    ScratchDir dir;
    std::string jpeg = read_file(std::string(VOLGUIDE_FUZZ_DIR) + "/corpus/image/rgb_4x3.jpg");
    ASSERT_GT(jpeg.size(), 100u);
    EXPECT_EQ(read_image(dir.write("small.jpg", jpeg)).width, 4);
    const size_t sof = jpeg.find("\xff\xc0");
    ASSERT_NE(sof, std::string::npos);
    jpeg.replace(sof + 5, 4, std::string("\x1f\x40\x1f\x40", 4));  // height, width 8000
    const std::string big = dir.write("big.jpg", jpeg);
    expect_error_containing([&] { read_image(big); },
                            fmt::format("big.jpg: a 8000 x 8000 image cannot fit in a file of {} bytes", jpeg.size()));

    const std::string png = dir.path("600.png");
    write_png(png, Image(600, 600));
    EXPECT_EQ(read_image(png).width, 600);
    setenv("VOLGUIDE_MEMORY_LIMIT_MB", "1", 1);
    expect_error_containing([&] { read_image(png); },
                            "a 600 x 600 image needs 11.0 MiB, more than the VOLGUIDE_MEMORY_LIMIT_MB budget of 1.0 MiB");
    unsetenv("VOLGUIDE_MEMORY_LIMIT_MB");
}

// OpenEXR allocates its decode buffers (whole blocks of scanlines, whole tiles) when it opens a
// file, before volguide sees the image's size: the fuzzer's 417-byte EXR declaring a 2178820 x 1
// data window of ZIP blocks (16 lines) made it allocate and free hundreds of MB (10 s under ASan).
// The header walk bounds those buffers first.
TEST(ResourceLimits, ExrDecodeBuffersAreBoundedBeforeOpenExrOpensTheFile) {
    const std::string strip =
        std::string(VOLGUIDE_FUZZ_DIR) + "/regression/image/timeout-exr-2178820-pixel-wide-strip-in-417-bytes.exr";
    expect_error_containing([&] { read_image(strip); },
                            "a 2178820 x 16 block of scanlines with 3 channels cannot fit in 417 bytes, even compressed");
}
