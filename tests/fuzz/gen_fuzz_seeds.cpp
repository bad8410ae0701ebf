// Writes the binary seeds of tests/fuzz/corpus/ (small valid files of each binary format), so the seed
// corpus can be regenerated when a format changes:  gen_fuzz_seeds tests/fuzz/corpus
// (target gen_fuzz_seeds, not built by default). Text seeds (XML, OBJ, PLY ascii) are kept as written.
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <png.h>
#include <stb/stb_image_write.h>

#include <cstdio>
// jpeglib.h needs FILE and size_t declared first.
#include <jpeglib.h>
#include <filesystem>
#include <fstream>

#include "volguide/core/sampler.h"
#include "volguide/core/warp.h"
#include "volguide/guiding/field_io.h"
#include "volguide/integrators/checkpoint_file.h"
#include "volguide/media/grid_data.h"
#include "volguide/render/image_io.h"
#include "volguide/render/render_part.h"
#include "support/serialized_writer.h"

using namespace volguide;
namespace fs = std::filesystem;

namespace {

void write_vol_seeds(const fs::path& dir) {
    GridData g;
    g.nx = 2, g.ny = 3, g.nz = 2, g.channels = 1;
    g.bbox = BBox3f(Point3f(0.f), Point3f(1.f));
    for (int i = 0; i < 12; ++i) g.values.push_back(0.1f * float(i));
    write_vol_file((dir / "grid_2x3x2.vol").string(), g);
    g.nx = 1, g.ny = 1, g.nz = 2, g.channels = 3;
    g.values = {1.f, 0.5f, 0.25f, 0.f, 2.f, 4.f};
    write_vol_file((dir / "rgb_1x1x2.vol").string(), g);
}

void write_vdb_seed(const fs::path& dir) {
    openvdb::initialize();
    auto grid = openvdb::FloatGrid::create(0.f);
    grid->setName("density");
    grid->setTransform(openvdb::math::Transform::createLinearTransform(0.5));
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) grid->tree().setValue(openvdb::Coord(x, y, z), float(x + y + z));
    openvdb::io::File file((dir / "density_2x2x2.vdb").string());
    file.setCompression(openvdb::io::COMPRESS_ACTIVE_MASK);  // no ZIP, and a small file: fast fuzzing
    file.write({grid});
    file.close();
}

void write_field_seed(const fs::path& dir) {
    std::vector<RadianceSample> s;
    for (int i = 0; i < 400; ++i) {
        Sampler r(3, 0, uint64_t(i));
        const Point3f p(r.next_1d(), r.next_1d(), r.next_1d());
        s.push_back({p, warp::square_to_uniform_sphere(r.next_2d()), Color3(1.f, 0.5f, 0.25f), 1.f, i % 4 == 0});
    }
    GuidingFieldSettings settings;
    settings.tree.max_samples = 150;
    settings.lobes = 2;
    settings.min_samples = 100;
    save_field((dir / "small.field").string(),
               GuidingField::build(BBox3f(Point3f(0.f), Point3f(1.f)), s, settings));
}

void write_part_seed(const fs::path& dir) {
    RenderPart part;
    part.mean = Image(2, 2);
    part.variance = Image(2, 2);
    part.weight.assign(4, 1.0);
    part.info.scene = "0123456789abcdef";
    part.info.scene_file = "scene.xml";
    part.info.seed = 7;
    part.info.field = "none";
    part.info.integrator = "volpath max_depth=4";
    part.info.samples = parse_ranges("0:4");
    write_part((dir / "part_2x2.exr").string(), part);
}

// A render checkpoint of a 2 x 2 film with second moments after two passes.
void write_checkpoint_seed(const fs::path& dir) {
    Checkpoint c;
    c.identity = {"0123456789abcdef", "scene.xml", "seed-build", "volpath max_depth=4",
                  {{"spp target", "8"}, {"seed", "7"}, {"resolution", "2x2"}}};
    c.state.passes = 2;
    c.state.spp_done = 2;
    c.state.film.weight.assign(4, 2.0);
    c.state.film.sum.assign(12, 0.5);
    c.state.film.sum2.assign(12, 0.25);
    c.state.samples = 8;
    c.state.integrator = "opaque";
    fs::create_directories(dir);
    save_checkpoint((dir / "film_2x2.ckpt").string(), c);
}

// Mitsuba .serialized meshes (issue 40): v4 float32 with normals and uvs, v3 float64 without, and a
// two-shape v4 file (the offset table with more than one entry).
void write_serialized_seeds(const fs::path& dir) {
    using namespace volguide::test;
    const auto write = [&](const char* name, const std::string& bytes) {
        std::ofstream(dir / name, std::ios::binary) << bytes;
    };
    write("quad_v4.serialized", serialized_file({serialized_quad()}, 4));
    SerializedShape d = serialized_quad(1.f);
    d.double_precision = true;
    d.normals.clear();
    d.uvs.clear();
    d.face_normals = true;
    write("quad_v3_double.serialized", serialized_file({d}, 3));
    write("two_v4.serialized", serialized_file({serialized_quad(), d}, 4));
}

// Images as textures read them (read_image): an 8-bit PNG and an EXR through volguide's writers, a
// JPEG, BMP and TGA through stb_image_write, and the PNG and JPEG variants libpng's and libjpeg's
// writers make.
void write_image_seeds(const fs::path& dir) {
    Image image(4, 3);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = Color3(float(i) / 12.f, 0.5f, 1.f - float(i) / 12.f);
    write_png((dir / "rgb_4x3.png").string(), image);
    write_exr((dir / "rgb_4x3.exr").string(), image);
    std::vector<unsigned char> bytes(image.pixels.size() * 3);
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = (unsigned char)(i * 21);
    stbi_write_jpg((dir / "rgb_4x3.jpg").string().c_str(), 4, 3, 3, bytes.data(), 90);
    stbi_write_bmp((dir / "rgb_4x3.bmp").string().c_str(), 4, 3, 3, bytes.data());
    stbi_write_tga((dir / "rgb_4x3.tga").string().c_str(), 4, 3, 3, bytes.data());

    // PNG colour types and depths beyond 8-bit RGB (libpng's simplified writer): 16-bit, gray with
    // alpha, a palette with transparency (tRNS).
    const auto png = [&](const char* name, png_uint_32 format, const void* pixels, const void* colormap = nullptr,
                         int entries = 0) {
        png_image out{};
        out.version = PNG_IMAGE_VERSION;
        out.width = 4;
        out.height = 3;
        out.format = format;
        out.colormap_entries = png_uint_32(entries);
        if (!png_image_write_to_file(&out, (dir / name).string().c_str(), 0, pixels, 0, colormap))
            std::fprintf(stderr, "gen_fuzz_seeds: %s: %s\n", name, out.message);
    };
    std::vector<uint16_t> deep(4 * 3 * 3);
    for (size_t i = 0; i < deep.size(); ++i) deep[i] = uint16_t(i * 5000);
    png("rgb16_4x3.png", PNG_FORMAT_LINEAR_RGB, deep.data());
    png("gray_alpha_4x3.png", PNG_FORMAT_GA, bytes.data());
    const uint8_t colormap[3 * 4] = {0, 0, 0, 0, 255, 128, 0, 200, 20, 40, 60, 255};
    const uint8_t indices[4 * 3] = {0, 1, 2, 1, 2, 0, 2, 0, 1, 1, 1, 2};
    png("palette_trns_4x3.png", PNG_FORMAT_RGBA_COLORMAP, indices, colormap, 3);

    // A progressive JPEG (several scans; libjpeg's writer).
    jpeg_compress_struct info{};
    jpeg_error_mgr error{};
    info.err = jpeg_std_error(&error);
    jpeg_create_compress(&info);
    FILE* file = std::fopen((dir / "progressive_4x3.jpg").string().c_str(), "wb");
    jpeg_stdio_dest(&info, file);
    info.image_width = 4;
    info.image_height = 3;
    info.input_components = 3;
    info.in_color_space = JCS_RGB;
    jpeg_set_defaults(&info);
    jpeg_simple_progression(&info);
    jpeg_start_compress(&info, TRUE);
    while (info.next_scanline < info.image_height) {
        JSAMPROW row = bytes.data() + size_t(info.next_scanline) * 4 * 3;
        jpeg_write_scanlines(&info, &row, 1);
    }
    jpeg_finish_compress(&info);
    jpeg_destroy_compress(&info);
    std::fclose(file);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: gen_fuzz_seeds CORPUS_DIR\n");
        return 2;
    }
    const fs::path root = argv[1];
    for (const char* t : {"vol", "vdb", "field", "exr_part", "serialized", "image"}) fs::create_directories(root / t);
    write_vol_seeds(root / "vol");
    write_vdb_seed(root / "vdb");
    write_field_seed(root / "field");
    write_part_seed(root / "exr_part");
    write_serialized_seeds(root / "serialized");
    write_image_seeds(root / "image");
    write_checkpoint_seed(root / "checkpoint");
    return 0;
}
