// Mitsuba's `.serialized` mesh format (versions 3 and 4), read with zlib. A file holds one or more
// shapes, each a 4-byte header (format id 0x041C, version; little endian) followed by a zlib stream:
// uint32 flags, [v4: the shape's name, NUL-terminated], uint64 vertex and triangle counts, then the
// positions, [normals], [uvs], [colours] as float32 or float64 per the flags, and uint32 triangle
// indices (uint64 when there are more than 2^32 vertices). The file ends with a table of the shapes'
// byte offsets (uint64 in v4, uint32 in v3) and the uint32 shape count; `shape_index` picks one.
// Bounded: every count is checked against what the compressed bytes left in the file can expand to
// (deflate's ratio is at most 1032:1) and against core/memory.h's budget before anything is allocated.
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "volguide/core/memory.h"
#include "volguide/geometry/shapes/mesh_files.h"

namespace volguide {

namespace {

constexpr uint16_t kFormatId = 0x041C;
constexpr uint64_t kMaxDeflateRatio = 1032;
enum : uint32_t {
    kHasNormals = 0x0001,
    kHasTexcoords = 0x0002,
    kHasColors = 0x0008,
    kFaceNormals = 0x0010,
    kSinglePrecision = 0x1000,
    kDoublePrecision = 0x2000,
};

struct SerializedError {
    std::string what;
};
[[noreturn]] void bad(std::string what) {
    throw SerializedError{std::move(what)};
}

uint64_t read_le(const std::string& data, size_t pos, int bytes) {
    uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | uint8_t(data[pos + size_t(i)]);
    return v;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) bad("cannot open the file");
    const std::streamoff size = in.tellg();
    if (size < 0) bad("cannot read the file");
    const uint64_t budget = memory_budget_bytes();
    if (budget > 0 && uint64_t(size) > budget)
        bad(fmt::format("the file ({}) exceeds {}", format_bytes(uint64_t(size)), memory_budget_description()));
    std::string data(size_t(size), '\0');
    in.seekg(0);
    if (!in.read(data.data(), size)) bad("cannot read the file");
    return data;
}

// The 4-byte shape header at `pos`; returns the version.
int check_header(const std::string& data, size_t pos) {
    if (pos > data.size() || data.size() - pos < 4)
        bad(fmt::format("truncated shape header at byte {}", pos));
    if (read_le(data, pos, 2) != kFormatId) bad(fmt::format("no serialized shape header at byte {}", pos));
    const int version = int(read_le(data, pos + 2, 2));
    if (version != 3 && version != 4) bad(fmt::format("unsupported format version {} (3 and 4 are)", version));
    return version;
}

// Byte offset of shape `index` from the table at the end of the file.
size_t shape_offset(const std::string& data, int version, uint64_t index) {
    if (index == 0) return 0;
    if (data.size() < 4) bad("the file is too short for its shape table");
    const uint64_t count = read_le(data, data.size() - 4, 4);
    if (index >= count)
        bad(fmt::format("shape_index {} is out of range: the file holds {} shape(s)", index, count));
    const uint64_t entry = version == 4 ? 8 : 4;
    const uint64_t from_end = 4 + entry * (count - index);
    if (count > data.size() / entry || from_end > data.size()) bad("the shape table does not fit in the file");
    const uint64_t offset = read_le(data, data.size() - size_t(from_end), int(entry));
    if (offset >= data.size()) bad(fmt::format("shape {} starts at byte {}, past the end of the file", index, offset));
    return size_t(offset);
}

// The decompressed bytes of one shape, pulled as they are needed.
class Inflater {
  public:
    Inflater(const std::string& data, size_t pos) : compressed_(data.size() - pos) {
        zs_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data() + pos));
        zs_.avail_in = uInt(std::min<uint64_t>(compressed_, std::numeric_limits<uInt>::max()));
        if (inflateInit(&zs_) != Z_OK) bad("zlib initialisation failed");
    }
    ~Inflater() { inflateEnd(&zs_); }
    Inflater(const Inflater&) = delete;
    Inflater& operator=(const Inflater&) = delete;

    void read(void* dst, size_t n, const char* what) {
        zs_.next_out = static_cast<Bytef*>(dst);
        while (n > 0) {
            const uInt chunk = uInt(std::min<size_t>(n, 1u << 30));
            zs_.avail_out = chunk;
            const int rc = ended_ ? Z_STREAM_END : inflate(&zs_, Z_NO_FLUSH);
            const size_t got = chunk - zs_.avail_out;
            n -= got;
            if (rc == Z_STREAM_END) ended_ = true;
            if (n > 0 && (rc == Z_STREAM_END || (rc == Z_BUF_ERROR && zs_.avail_in == 0)))
                bad(fmt::format("the compressed data ends inside the {}", what));
            if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR)
                bad(fmt::format("corrupt compressed data in the {} ({})", what, zs_.msg ? zs_.msg : "zlib error"));
            if (got == 0 && rc == Z_BUF_ERROR) bad(fmt::format("corrupt compressed data in the {}", what));
        }
    }
    template <typename T>
    T value(const char* what) {
        T v;
        read(&v, sizeof(T), what);  // little endian, as the format and the supported platforms
        return v;
    }
    // What the rest of the stream can expand to at most.
    uint64_t max_remaining() const { return uint64_t(zs_.avail_in) * kMaxDeflateRatio + 64; }

  private:
    z_stream zs_{};
    uint64_t compressed_;
    bool ended_ = false;
};

struct Layout {
    uint32_t flags = 0;
    uint64_t vertices = 0, triangles = 0;
    size_t scalar = 4, index = 4;
    uint64_t vertex_bytes() const {
        int per = 3 + ((flags & kHasNormals) ? 3 : 0) + ((flags & kHasTexcoords) ? 2 : 0) + ((flags & kHasColors) ? 3 : 0);
        return uint64_t(per) * scalar;
    }
};

void skip_name(Inflater& in) {
    for (int i = 0; i < 65536; ++i)
        if (in.value<char>("shape name") == '\0') return;
    bad("the shape name is longer than 65536 bytes (no terminating NUL)");
}

Layout read_layout(Inflater& in, int version) {
    Layout l;
    l.flags = in.value<uint32_t>("mesh flags");
    const bool single = l.flags & kSinglePrecision, dbl = l.flags & kDoublePrecision;
    if (single == dbl) bad(fmt::format("the mesh flags 0x{:x} name neither or both float precisions", l.flags));
    l.scalar = dbl ? 8 : 4;
    if (version == 4) skip_name(in);
    l.vertices = in.value<uint64_t>("vertex count");
    l.triangles = in.value<uint64_t>("triangle count");
    if (l.vertices > std::numeric_limits<uint32_t>::max())
        bad(fmt::format("{} vertices: more than volguide's 32-bit indices address", l.vertices));
    l.index = 4;
    return l;
}

// Sizes sanity: what the counts need fits in what the stream can still hold and in the budget.
void check_sizes(const Layout& l, const Inflater& in) {
    const uint64_t max = std::numeric_limits<uint64_t>::max() / 64;
    if (l.vertices > max / l.vertex_bytes() || l.triangles > max / (3 * l.index))
        bad(fmt::format("impossible counts ({} vertices, {} triangles)", l.vertices, l.triangles));
    const uint64_t stored = l.vertices * l.vertex_bytes() + l.triangles * 3 * l.index;
    if (stored > in.max_remaining())
        bad(fmt::format("{} vertices and {} triangles need {} of data, more than the rest of the file can hold",
                        l.vertices, l.triangles, format_bytes(stored)));
    const uint64_t in_memory = l.vertices * (12 + 12 + 8) + l.triangles * 12;
    const uint64_t budget = memory_budget_bytes();
    if (budget > 0 && in_memory > budget)
        bad(fmt::format("{} vertices and {} triangles need {}, more than {}", l.vertices, l.triangles,
                        format_bytes(in_memory), memory_budget_description()));
}

// n tuples of `dim` scalars (float32 or float64), all finite.
std::vector<float> read_scalars(Inflater& in, const Layout& l, int dim, const char* what) {
    const size_t n = size_t(l.vertices) * size_t(dim);
    std::vector<float> out(n);
    if (l.scalar == 4) {
        in.read(out.data(), n * 4, what);
    } else {
        std::vector<double> tmp(n);
        in.read(tmp.data(), n * 8, what);
        for (size_t i = 0; i < n; ++i) out[i] = float(tmp[i]);
    }
    for (float v : out)
        if (!std::isfinite(v)) bad(fmt::format("a non-finite value among the {}", what));
    return out;
}

void read_vertices(Inflater& in, const Layout& l, TriangleMesh& mesh) {
    const std::vector<float> p = read_scalars(in, l, 3, "positions");
    mesh.positions.resize(size_t(l.vertices));
    for (size_t i = 0; i < mesh.positions.size(); ++i) mesh.positions[i] = Point3f(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    if (l.flags & kHasNormals) {
        const std::vector<float> nv = read_scalars(in, l, 3, "normals");
        mesh.normals.resize(size_t(l.vertices));
        for (size_t i = 0; i < mesh.normals.size(); ++i) mesh.normals[i] = Normal3f(nv[3 * i], nv[3 * i + 1], nv[3 * i + 2]);
    }
    if (l.flags & kHasTexcoords) {
        const std::vector<float> t = read_scalars(in, l, 2, "texture coordinates");
        mesh.uvs.resize(size_t(l.vertices));
        for (size_t i = 0; i < mesh.uvs.size(); ++i) mesh.uvs[i] = Vec2f(t[2 * i], t[2 * i + 1]);
    }
    if (l.flags & kHasColors) (void)read_scalars(in, l, 3, "vertex colours");  // not used by volguide
}

void read_indices(Inflater& in, const Layout& l, TriangleMesh& mesh) {
    mesh.indices.resize(size_t(l.triangles) * 3);
    in.read(mesh.indices.data(), mesh.indices.size() * 4, "triangle indices");
    for (uint32_t i : mesh.indices)
        if (i >= l.vertices) bad(fmt::format("triangle index {} is out of range ({} vertices)", i, l.vertices));
}

}  // namespace

SerializedMesh read_serialized(const std::string& path, int64_t shape_index, const SourceLocation& loc) {
    try {
        if (shape_index < 0) bad(fmt::format("shape_index must be >= 0, got {}", shape_index));
        const std::string data = read_file(path);
        const size_t offset = shape_offset(data, check_header(data, 0), uint64_t(shape_index));
        const int version = check_header(data, offset);
        Inflater in(data, offset + 4);
        const Layout layout = read_layout(in, version);
        check_sizes(layout, in);
        SerializedMesh out;
        out.face_normals = (layout.flags & kFaceNormals) != 0;
        read_vertices(in, layout, out.mesh);
        read_indices(in, layout, out.mesh);
        return out;
    } catch (const SerializedError& e) {
        fail(loc, "error while loading serialized mesh \"{}\" (shape {}): {}", path, shape_index, e.what);
    } catch (const std::bad_alloc&) {
        fail(loc, "error while loading serialized mesh \"{}\": out of memory", path);
    }
}

}  // namespace volguide
