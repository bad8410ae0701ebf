// Mitsuba's binary .vol grid format: "VOL", version byte 3, int32 encoding (1 = float32),
// int32 xres, yres, zres, channels, six float32 bbox values (xmin ymin zmin xmax ymax zmax), then
// xres*yres*zres*channels float32 values with x fastest. Little endian.
#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "volguide/core/atomic_write.h"
#include "volguide/core/error.h"
#include "volguide/media/grid_data.h"

namespace volguide {

namespace {

static_assert(std::endian::native == std::endian::little, ".vol reading assumes a little-endian host");

[[noreturn]] void vol_fail(const std::string& path, const std::string& what) {
    throw InputError(SourceLocation{path, 0}, fmt::format("\"{}\": {}", path, what));
}

}  // namespace

namespace {

// Reads and checks the header of `in`, opened from `path`: the grid has no values yet, `count` is the
// number of floats that follow (checked against the file's size before anything is allocated).
GridData read_header(std::ifstream& in, const std::string& path, uint64_t& count) {
    if (!in) vol_fail(path, "cannot open the .vol file");
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(0, std::ios::beg);
    const std::streamoff header_size = 48;
    if (size < header_size) vol_fail(path, fmt::format("truncated .vol header ({} bytes, need 48)", size));

    char header[48];
    in.read(header, header_size);
    if (header[0] != 'V' || header[1] != 'O' || header[2] != 'L') vol_fail(path, "not a .vol file (no \"VOL\" magic)");
    if (header[3] != 3) vol_fail(path, fmt::format("unsupported .vol version {} (expected 3)", int(header[3])));
    int32_t ints[5];
    std::memcpy(ints, header + 4, sizeof(ints));
    const int32_t encoding = ints[0];
    if (encoding != 1) vol_fail(path, fmt::format("unsupported .vol encoding {} (only 1 = float32)", encoding));
    GridData g;
    g.nx = ints[1];
    g.ny = ints[2];
    g.nz = ints[3];
    g.channels = ints[4];
    if (g.nx < 1 || g.ny < 1 || g.nz < 1)
        vol_fail(path, fmt::format("invalid .vol resolution {}x{}x{}", g.nx, g.ny, g.nz));
    if (g.channels != 1 && g.channels != 3)
        vol_fail(path, fmt::format("{} channels (only 1 or 3 are supported)", g.channels));
    float box[6];
    std::memcpy(box, header + 24, sizeof(box));
    g.bbox = BBox3f(Point3f(box[0], box[1], box[2]), Point3f(box[3], box[4], box[5]));

    // Dimensions up to 2^31 each would overflow a 64-bit product, so each factor is checked against
    // what the file can still hold before it is multiplied in.
    const uint64_t capacity = uint64_t(size - header_size) / 4;
    count = uint64_t(g.channels);
    for (int32_t n : {g.nx, g.ny, g.nz}) {
        if (uint64_t(n) > capacity / count)  // count * n > capacity, tested without overflowing
            vol_fail(path, fmt::format("truncated .vol data ({} bytes hold {} floats, but {}x{}x{}x{} are declared)",
                                       size, capacity, g.nx, g.ny, g.nz, g.channels));
        count *= uint64_t(n);
    }
    return g;
}

}  // namespace

GridData read_vol_header(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    uint64_t count = 0;
    return read_header(in, path, count);
}

GridData read_vol_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    uint64_t count = 0;
    GridData g = read_header(in, path, count);
    g.values.resize(count);
    in.read(reinterpret_cast<char*>(g.values.data()), std::streamsize(4 * count));
    if (!in) vol_fail(path, "read error in the .vol data");
    return g;
}

void write_vol_file(const std::string& path, const GridData& g) {
    if (g.values.size() != size_t(g.nx) * g.ny * g.nz * g.channels)
        throw std::runtime_error("\"" + path + "\": grid size does not match its values");
    const BBox3f box = g.bbox.valid() ? g.bbox : BBox3f(Point3f(0.f), Point3f(1.f));
    const std::string error = write_atomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        const char magic[4] = {'V', 'O', 'L', 3};
        const int32_t ints[5] = {1, g.nx, g.ny, g.nz, g.channels};
        const float b[6] = {box.lo.x, box.lo.y, box.lo.z, box.hi.x, box.hi.y, box.hi.z};
        out.write(magic, 4);
        out.write(reinterpret_cast<const char*>(ints), sizeof(ints));
        out.write(reinterpret_cast<const char*>(b), sizeof(b));
        out.write(reinterpret_cast<const char*>(g.values.data()), std::streamsize(g.values.size() * sizeof(float)));
        out.close();
        if (!out) throw std::runtime_error("write failed");
    });
    if (!error.empty()) throw std::runtime_error("\"" + path + "\": cannot write the .vol file: " + error);
}

}  // namespace volguide
