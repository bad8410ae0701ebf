#include "volguide/media/vdb_header_check.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <vector>

#include "volguide/core/error.h"
#include "volguide/core/memory.h"

namespace volguide {

namespace {

// Layout (little endian): int64 magic 0x56444220, uint32 file version, uint32 library major and minor,
// char has-grid-offsets, 36-char UUID, the file's metadata map, int32 grid count, then per grid a
// descriptor (name, type and instance-parent strings, int64 grid, block and end offsets) followed by
// the grid, the next descriptor starting at the end offset; at each grid offset: uint32
// compression, then the grid's metadata map, then its transform (a map type string and the map's
// fixed-size values). Strings are uint32 length + bytes; a metadata map is uint32 count, then per entry
// name and type strings and uint32 size + value.
//
// OpenVDB reads a value of a type it registers by that type's layout, not by the declared size: a
// "vec4i" declared 12 bytes long is read as 16, and every later length comes from the wrong bytes (a
// fuzzed file made it allocate a 1.7 GB string from the characters of the next name). So a
// registered fixed-size type must declare exactly its size; "string" and unregistered types are read
// by the declared size; "__delayedload" (io::DelayedLoadMetadata) is walked inside its declared size.
constexpr uint32_t kMinFormat = 222;  // OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION

// io::DelayedLoadMetadata: uint32 count, then the leaf mask (int8 per leaf) and the leaves' compressed
// sizes (int64 per leaf), each as uint32 byte count + Blosc buffer, or 0 + the raw array; a byte count
// of 0xffffffff for the sizes means none are stored.
constexpr uint32_t kNoCompressedSizes = 0xffffffffu;
constexpr uint64_t kBloscHeaderBytes = 16;
// Every leaf costs at least its 64-byte value mask in the file's topology, so a file of N bytes holds
// at most N / 64 leaves; the count sizes two arrays OpenVDB allocates before reading them.
constexpr uint64_t kMinBytesPerLeaf = 64;

// The transform's map, read by its type's layout (math/Maps.h: Vec3d = 24 bytes, Mat4d = 128).
// NonlinearFrustumMap is not walked: volguide reads scale-and-translate grids only, so it is refused.
uint64_t map_bytes(const std::string& type) {
    if (type == "AffineMap" || type == "UnitaryMap") return 128;         // Mat4d (Unitary: its AffineMap)
    if (type == "ScaleMap" || type == "UniformScaleMap") return 5 * 24;  // scale, voxel size, 3 inverses
    if (type == "TranslationMap") return 24;
    if (type == "ScaleTranslateMap" || type == "UniformScaleTranslateMap") return 6 * 24;  // + translation
    return 0;
}

// After the transform: int32 buffer count (1 since OpenVDB 3), then the root node: background value,
// uint32 tile and child counts, each tile (int32 origin[3], value, bool active), each child (int32
// origin[3], then its topology, which starts with the child and value masks of a 32^3 node: 8 KiB).
// OpenVDB allocates a 32^3 internal node (264 KiB of child table and masks) per declared child
// before reading it: a fuzzed 10 KB file declared 1.7 G of them. Value sizes of the tree types
// openvdb::initialize() registers; a "_HalfFloat" grid still stores its root values in full.
constexpr uint64_t kRootChildMinBytes = 12 + 2 * 4096;
constexpr uint64_t kRootChildMemoryBytes = 32768 * 8 + 2 * 4096;
uint64_t tree_value_bytes(std::string type) {
    const std::string half = "_HalfFloat";
    if (type.size() > half.size() && type.compare(type.size() - half.size(), half.size(), half) == 0)
        type.resize(type.size() - half.size());
    static const std::map<std::string, uint64_t, std::less<>> sizes = {
        {"Tree_bool_5_4_3", 1},     {"Tree_mask_5_4_3", 1},    {"Tree_float_5_4_3", 4},
        {"Tree_double_5_4_3", 8},   {"Tree_int32_5_4_3", 4},   {"Tree_int64_5_4_3", 8},
        {"Tree_vec3i_5_4_3", 12},   {"Tree_vec3s_5_4_3", 12},  {"Tree_vec3d_5_4_3", 24},
        {"Tree_ptidx32_5_4_3", 4},  {"Tree_ptdataidx32_5_4_3", 4}};
    const auto it = sizes.find(type);
    return it == sizes.end() ? 0 : it->second;
}

class VdbWalker {
  public:
    VdbWalker(const std::string& path, std::ifstream& in, uint64_t size) : path_(path), in_(in), size_(size) {}

    void walk() {
        if (size_ < 57 || u32_at(0) != 0x56444220 || u32_at(4) != 0)
            fail("not a .vdb file (no OpenVDB magic number)");
        const uint32_t version = u32_at(8);
        if (version < kMinFormat)
            fail(fmt::format("file format {} is older than the {} volguide reads", version, kMinFormat));
        if (byte_at(20) == 0) fail("a stream without grid offsets (volguide reads files written by io::File)");
        pos_ = 57;  // after magic, version, library version, the offsets flag and the UUID
        walk_metadata("the file's metadata");
        const int32_t grids = int32_t(read_u32("grid count"));
        // A descriptor is at least three empty strings and three offsets: 36 bytes.
        if (grids < 0 || uint64_t(grids) > (size_ - pos_) / 36)
            fail(fmt::format("{} grids declared in {} bytes", grids, size_ - pos_));
        std::vector<uint64_t> offsets;
        std::vector<std::string> types;
        std::vector<bool> instances;
        for (int32_t g = 0; g < grids; ++g) {
            skip_string("grid name");
            types.push_back(read_string("grid type"));
            instances.push_back(!read_string("instance parent").empty());
            const uint64_t grid = read_u64("grid offset"), block = read_u64("block offset"), end = read_u64("end offset");
            if (pos_ > grid || grid > block || block > end || end > size_)
                fail(fmt::format("grid {} has offsets {}, {}, {} outside the file's {} bytes", g, grid, block, end, size_));
            offsets.push_back(grid);
            pos_ = end;  // each descriptor is followed by its grid; the next descriptor starts after it
        }
        for (size_t g = 0; g < offsets.size(); ++g) {
            pos_ = offsets[g];
            read_u32("grid compression");
            walk_metadata("a grid's metadata");
            const std::string map = read_string("grid transform's map type");
            const uint64_t bytes = map_bytes(map);
            if (bytes == 0)
                fail(fmt::format("grid {} has a \"{}\" transform (volguide reads scale and translation maps)", g, map));
            need(bytes, "the grid transform");
            pos_ += bytes;
            // An instance shares its parent's tree (read at the parent's offset); a tree type OpenVDB
            // does not register is refused by OpenVDB before its topology is read.
            const uint64_t value = tree_value_bytes(types[g]);
            if (!instances[g] && value > 0) walk_root(value);
        }
    }

  private:
    void walk_root(uint64_t value) {
        const uint32_t buffers = read_u32("tree buffer count");
        if (buffers != 1) fail(fmt::format("a tree declares {} buffers (OpenVDB writes 1)", buffers));
        need(value, "the tree's background value");
        pos_ += value;
        const uint32_t tiles = read_u32("root tile count"), children = read_u32("root child count");
        const uint64_t left = size_ - pos_, tile_bytes = 12 + value + 1;
        if (tiles > left / tile_bytes)
            fail(fmt::format("the tree's root declares {} tiles of {} bytes in {} bytes", tiles, tile_bytes, left));
        if (children > (left - uint64_t(tiles) * tile_bytes) / kRootChildMinBytes)
            fail(fmt::format("the tree's root declares {} child nodes (at least {} bytes each) in {} bytes", children,
                             kRootChildMinBytes, left - uint64_t(tiles) * tile_bytes));
        const uint64_t budget = memory_budget_bytes();
        if (budget > 0 && uint64_t(children) * kRootChildMemoryBytes > budget)
            fail(fmt::format("the tree's root declares {} child nodes ({} in memory), more than {}", children,
                             format_bytes(uint64_t(children) * kRootChildMemoryBytes), memory_budget_description()));
    }
    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(SourceLocation{path_, 0}, fmt::format("\"{}\": cannot read the .vdb file: {}", path_, what));
    }
    void read_at(uint64_t offset, char* out, size_t n) {
        in_.seekg(std::streamoff(offset));
        if (!in_.read(out, std::streamsize(n))) fail("read error");
    }
    uint32_t u32_at(uint64_t offset) {
        char b[4];
        read_at(offset, b, 4);
        uint32_t v;
        std::memcpy(&v, b, 4);
        return v;
    }
    char byte_at(uint64_t offset) {
        char c;
        read_at(offset, &c, 1);
        return c;
    }
    void need(uint64_t n, const std::string& what) {
        if (pos_ > size_ || n > size_ - pos_)
            fail(fmt::format("{} ({} bytes at offset {}) runs past the end of the file ({} bytes)", what, n, pos_, size_));
    }
    uint32_t read_u32(const std::string& what) {
        need(4, what);
        const uint32_t v = u32_at(pos_);
        pos_ += 4;
        return v;
    }
    uint64_t read_u64(const std::string& what) {
        need(8, what);
        char b[8];
        read_at(pos_, b, 8);
        uint64_t v;
        std::memcpy(&v, b, 8);
        pos_ += 8;
        return v;
    }
    void skip_string(const std::string& what) {
        const uint32_t n = read_u32("length of the " + what);
        need(n, "the " + what);
        pos_ += n;
    }
    std::string read_string(const std::string& what) {
        const uint32_t n = read_u32("length of the " + what);
        need(n, "the " + what);
        std::string s(n, '\0');
        if (n > 0) read_at(pos_, s.data(), n);
        pos_ += n;
        return s;
    }
    void walk_metadata(const std::string& what) {
        const uint32_t count = read_u32("entry count of " + what);
        // An entry is at least two empty strings and an empty value: 12 bytes.
        if (pos_ > size_ || count > (size_ - pos_) / 12)
            fail(fmt::format("{} declares {} entries in {} bytes", what, count, size_ - std::min(pos_, size_)));
        for (uint32_t i = 0; i < count; ++i) {
            skip_string("metadata name");
            const std::string type = read_string("metadata type");
            const uint32_t n = read_u32("metadata size");
            need(n, "a metadata value");
            if (const std::optional<uint32_t> layout = vdb_metadata_layout_bytes(type); layout && *layout != n)
                fail(fmt::format("a \"{}\" metadata value declares {} bytes; OpenVDB reads {}", type, n, *layout));
            if (type == "__delayedload" && n > 0) walk_delayed_load(pos_, pos_ + n);
            pos_ += n;
        }
    }
    // One array of the delayed-load metadata at [at, end): uint32 byte count, then a Blosc buffer of
    // that many bytes holding count elements, or (byte count 0) the raw elements. Returns its end.
    uint64_t walk_delayed_load_array(uint64_t at, uint64_t end, uint32_t bytes, uint64_t count, uint64_t element,
                                     const char* what) {
        const uint64_t stored = bytes > 0 ? bytes : count * element;
        if (stored > end - at)
            fail(fmt::format("the delayed-load {} ({} bytes at offset {}) runs past its metadata value", what, stored, at));
        if (bytes > 0) {
            // OpenVDB takes the sizes from the Blosc header: the uncompressed one sizes its buffer, and
            // Blosc reads as many compressed bytes as its header says.
            if (bytes < kBloscHeaderBytes)
                fail(fmt::format("the delayed-load {} is a {}-byte Blosc buffer (its header alone is {})", what, bytes,
                                 kBloscHeaderBytes));
            const uint32_t uncompressed = u32_at(at + 4), compressed = u32_at(at + 12);
            if (uncompressed != count * element || compressed != bytes)
                fail(fmt::format("the delayed-load {}'s Blosc header declares {} bytes from {} ({} from {} expected)",
                                 what, uncompressed, compressed, count * element, bytes));
        }
        return at + stored;
    }
    void walk_delayed_load(uint64_t at, uint64_t end) {
        if (end - at < 12) fail(fmt::format("delayed-load metadata of {} bytes (at least 12)", end - at));
        const uint32_t count = u32_at(at);
        if (count > size_ / kMinBytesPerLeaf)
            fail(fmt::format("delayed-load metadata for {} leaves in a file of {} bytes", count, size_));
        at = walk_delayed_load_array(at + 8, end, u32_at(at + 4), count, 1, "leaf mask");
        if (end - at < 4) fail("the delayed-load compressed sizes run past their metadata value");
        const uint32_t bytes = u32_at(at);
        if (bytes != kNoCompressedSizes) walk_delayed_load_array(at + 4, end, bytes, count, 8, "compressed sizes");
    }

    const std::string& path_;
    std::ifstream& in_;
    uint64_t size_;
    uint64_t pos_ = 0;
};

}  // namespace

std::optional<uint32_t> vdb_metadata_layout_bytes(const std::string& type) {
    // The fixed-size metadata types openvdb::initialize() registers (OpenVDB 10; test_media_vdb checks
    // this table against the library's own sizes), with the sizes TypedMetadata<T>::readValue reads.
    static const std::map<std::string, uint32_t, std::less<>> layouts = {
        {"bool", 1},   {"int32", 4},   {"int64", 8},   {"float", 4},   {"double", 8},  {"vec2i", 8},
        {"vec2s", 8},  {"vec2d", 16},  {"vec3i", 12},  {"vec3s", 12},  {"vec3d", 24},  {"vec4i", 16},
        {"vec4s", 16}, {"vec4d", 32},  {"mat4s", 64},  {"mat4d", 128}, {"ptidx32", 4}, {"ptidx64", 8},
        {"ptdataidx32", 4}, {"ptdataidx64", 8}};
    const auto it = layouts.find(type);
    if (it == layouts.end()) return std::nullopt;
    return it->second;
}

void check_vdb_header(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(SourceLocation{path, 0}, fmt::format("\"{}\": cannot open the .vdb file", path));
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    VdbWalker(path, in, uint64_t(std::max<std::streamoff>(size, 0))).walk();
}

}  // namespace volguide
