#include "volguide/media/vdb_header_check.h"

#include <algorithm>
#include <array>
#include <cmath>
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
constexpr uint64_t kBloscHeaderBytes = 16, kBloscPadBytes = 128;
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

// After the transform the tree (tree/RootNode.h, InternalNode.h, LeafNode.h): int32 buffer count (1
// since OpenVDB 3), then the topology — the root's background value, uint32 tile and child counts, each
// tile (int32 origin[3], value, bool active), each child (int32 origin[3], then a 32^3 internal node) —
// and then the voxel buffers of every leaf, in the topology's order. An internal node is its child
// and value masks, its values (compressed, below), then each child's topology in bit order: 16^3
// internal nodes under the 32^3 ones, leaves (a 64-byte value mask) under those. OpenVDB allocates
// every node before reading it and reads on after the stream ran dry (a failed read leaves zeroes), so
// a 32^3 node whose child mask is full makes it allocate 32768 16^3 nodes (1.1 GB) from an 8 KB
// file: every node must be in the file and their memory within the budget before OpenVDB starts.
constexpr uint64_t kRootDim = 32 * 32 * 32, kInternalDim = 16 * 16 * 16, kLeafDim = 8 * 8 * 8;
constexpr uint64_t kLeafMaskBytes = kLeafDim / 8;

// io/Compression.h: the grid's compression flags and the per-node metadata byte.
constexpr uint32_t kCompressZip = 0x1, kCompressActiveMask = 0x2, kCompressBlosc = 0x4;
enum : uint8_t {
    kNoMaskOrInactiveVals = 0,
    kNoMaskAndMinusBg = 1,
    kNoMaskAndOneInactiveVal = 2,
    kMaskAndNoInactiveVals = 3,
    kMaskAndOneInactiveVal = 4,
    kMaskAndTwoInactiveVals = 5,
    kNoMaskAndAllVals = 6,
};

// How a tree type's nodes are stored: its value size, the size of a value saved as half float (0 for
// types that are not real), and its leaves' buffers (values compressed like a node's; bool leaves: the
// value mask, origin and a 64-byte bit buffer; mask leaves: the mask and origin). Point grids' leaves
// store attribute arrays that are not walked: only their root is bounded, and read_vdb_file refuses
// their type before OpenVDB reads their tree. The tree types openvdb::initialize() registers; a
// "_HalfFloat" suffix only marks the grid as saved as half (GridDescriptor strips it).
enum class LeafKind { Values, Bool, Mask, Points };
struct TreeLayout {
    uint64_t value = 0, half = 0;
    LeafKind leaf = LeafKind::Values;
};
std::optional<TreeLayout> tree_layout(std::string type) {
    const std::string half = "_HalfFloat";
    if (type.size() > half.size() && type.compare(type.size() - half.size(), half.size(), half) == 0)
        type.resize(type.size() - half.size());
    static const std::map<std::string, TreeLayout, std::less<>> layouts = {
        {"Tree_bool_5_4_3", {1, 0, LeafKind::Bool}},         {"Tree_mask_5_4_3", {1, 0, LeafKind::Mask}},
        {"Tree_float_5_4_3", {4, 2, LeafKind::Values}},      {"Tree_double_5_4_3", {8, 2, LeafKind::Values}},
        {"Tree_int32_5_4_3", {4, 0, LeafKind::Values}},      {"Tree_int64_5_4_3", {8, 0, LeafKind::Values}},
        {"Tree_vec3i_5_4_3", {12, 0, LeafKind::Values}},     {"Tree_vec3s_5_4_3", {12, 6, LeafKind::Values}},
        {"Tree_vec3d_5_4_3", {24, 6, LeafKind::Values}},     {"Tree_ptidx32_5_4_3", {4, 0, LeafKind::Points}},
        {"Tree_ptdataidx32_5_4_3", {4, 0, LeafKind::Points}}};
    const auto it = layouts.find(type);
    if (it == layouts.end()) return std::nullopt;
    return it->second;
}

// What OpenVDB holds in memory per node it creates (a table entry per child or value, the masks),
// an upper bound: a table entry is a pointer or a value.
uint64_t internal_node_memory(uint64_t dim, uint64_t value) { return dim * (8 + value) + 2 * dim / 8; }
uint64_t leaf_node_memory(uint64_t value) { return kLeafDim * value + 2 * kLeafMaskBytes + 64; }

uint64_t popcount(const std::vector<uint64_t>& words) {
    uint64_t n = 0;
    for (uint64_t w : words) n += uint64_t(__builtin_popcountll(w));
    return n;
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
        std::vector<uint64_t> offsets, blocks, ends;
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
            blocks.push_back(block);
            ends.push_back(end);
            pos_ = end;  // each descriptor is followed by its grid; the next descriptor starts after it
        }
        bool has_instances = false, has_points = false;
        for (size_t g = 0; g < offsets.size(); ++g) {
            pos_ = offsets[g];
            const uint32_t compression = read_u32("grid compression");
            const std::optional<bool> saved_as_half = walk_metadata("a grid's metadata");
            const std::string map = read_string("grid transform's map type");
            const uint64_t bytes = map_bytes(map);
            if (bytes == 0)
                fail(fmt::format("grid {} has a \"{}\" transform (volguide reads scale and translation maps)", g, map));
            need(bytes, "the grid transform");
            check_scale_map(g, map);
            pos_ += bytes;
            // An instance shares its parent's tree (read at the parent's offset); a tree type OpenVDB
            // does not register is refused by OpenVDB before its topology is read.
            const std::optional<TreeLayout> layout = tree_layout(types[g]);
            has_instances = has_instances || instances[g];
            if (instances[g] || !layout) continue;
            has_points = has_points || layout->leaf == LeafKind::Points;
            // Grid::readTopology/readBuffers read values as half floats when the grid's metadata says
            // so (readMeta replaces what the descriptor's "_HalfFloat" suffix set); writers set both.
            const bool suffix = types[g].size() > 10 && types[g].compare(types[g].size() - 10, 10, "_HalfFloat") == 0;
            if (saved_as_half.value_or(false) != suffix)
                fail(fmt::format("grid {}'s type \"{}\" and its is_saved_as_half_float metadata disagree", g, types[g]));
            walk_tree(*layout, compression, suffix, blocks[g]);
            // io::Archive writes the descriptor's offsets from where the buffers began and ended.
            if (layout->leaf != LeafKind::Points && pos_ != ends[g])
                fail(fmt::format("grid {}'s voxel buffers end at offset {}, its descriptor says {}", g, pos_, ends[g]));
        }
        // Reading an instance reads its parent's tree, found by name: every tree it could be must be walked.
        if (has_instances && has_points)
            fail("instanced grids in a file with point grids (their trees are not checked before reading)");
    }

  private:
    // A scale map stores its scale and the values derived from it (voxel size, inverse, ...), and
    // OpenVDB reads them all without deriving them again: a file whose stored values disagree reads
    // as one scale and converts to an affine map as another (a fuzzed file's getAffineMap() threw
    // "nearly singular" past a frame that cannot unwind). OpenVDB writes them consistent.
    void check_scale_map(size_t g, const std::string& map) {
        if (map.find("Scale") == std::string::npos) return;
        const uint64_t at = pos_ + (map.find("Translate") != std::string::npos ? 24 : 0);
        double v[15];
        read_at(at, reinterpret_cast<char*>(v), sizeof(v));
        for (int i = 0; i < 3; ++i) {
            const double scale = v[i], voxel = v[3 + i], inverse = v[6 + i];
            bool ok = std::isfinite(scale) && scale != 0.0 && std::isfinite(1.0 / scale);
            ok = ok && std::abs(voxel - std::abs(scale)) <= 1e-6 * std::abs(scale);
            ok = ok && std::abs(inverse * scale - 1.0) <= 1e-6;
            for (int k = 9; k < 15; ++k) ok = ok && std::isfinite(v[k]);
            if (!ok)
                fail(fmt::format("grid {}'s {} stores scale {}, voxel size {} and inverse {} along axis {} (inconsistent)",
                                 g, map, scale, voxel, inverse, i));
        }
    }
    // Walks the tree at pos_ whose buffers start at `block` (the descriptor's block offset).
    void walk_tree(const TreeLayout& layout, uint32_t compression, bool half, uint64_t block) {
        layout_ = layout;
        compression_ = compression;
        from_half_ = half && layout.half > 0;
        element_ = from_half_ ? layout.half : layout.value;
        memory_ = 0;
        leaf_active_.clear();
        const uint32_t buffers = read_u32("tree buffer count");
        if (buffers != 1) fail(fmt::format("a tree declares {} buffers (OpenVDB writes 1)", buffers));
        need(layout.value, "the tree's background value");
        pos_ += layout.value;
        const uint32_t tiles = read_u32("root tile count"), children = read_u32("root child count");
        const uint64_t tile_bytes = 12 + layout.value + 1;
        if (pos_ > size_ || tiles > (size_ - pos_) / tile_bytes)
            fail(fmt::format("the tree's root declares {} tiles of {} bytes in {} bytes", tiles, tile_bytes,
                             size_ - std::min(pos_, size_)));
        pos_ += uint64_t(tiles) * tile_bytes;
        // Each child is at least its origin and a 32^3 node's two masks.
        if (children > (size_ - pos_) / (12 + kRootDim / 4))
            fail(fmt::format("the tree's root declares {} child nodes (at least {} bytes each) in {} bytes", children,
                             12 + kRootDim / 4, size_ - pos_));
        if (layout.leaf == LeafKind::Points) {
            // Only the root is bounded (see TreeLayout): its children's 32^3 nodes.
            add_memory(uint64_t(children) * internal_node_memory(kRootDim, layout.value), "the root's child nodes");
            return;
        }
        // RootNode::readBuffers visits its children in the order of their origins, the order in which
        // OpenVDB writes them: the buffers below follow the topology's order only if the file's does.
        std::array<int32_t, 3> last{};
        for (uint32_t c = 0; c < children; ++c) {
            std::array<int32_t, 3> origin;
            for (int32_t& o : origin) o = int32_t(read_u32("a root child's origin"));
            if (c > 0 && !(last < origin))
                fail(fmt::format("the root's child nodes are not in the order OpenVDB writes them (child {} at ({}, {}, {}))",
                                 c, origin[0], origin[1], origin[2]));
            last = origin;
            walk_internal_topology(kRootDim);
        }
        if (pos_ != block)
            fail(fmt::format("the tree's topology ends at offset {}, its descriptor's buffers start at {}", pos_, block));
        for (uint64_t active : leaf_active_) walk_leaf_buffer(active);
    }
    // A 32^3 or 16^3 internal node's topology and, below it, its children's.
    void walk_internal_topology(uint64_t dim) {
        add_memory(internal_node_memory(dim, layout_.value), "the tree's internal nodes");
        const uint64_t mask_bytes = dim / 8;
        const std::vector<uint64_t> child_mask = read_mask(mask_bytes, "an internal node's child mask");
        const uint64_t active = popcount(read_mask(mask_bytes, "an internal node's value mask"));
        walk_compressed_values(dim, active, layout_.value);
        for (size_t w = 0; w < child_mask.size(); ++w)
            for (uint64_t bits = child_mask[w]; bits != 0; bits &= bits - 1) {
                if (dim == kRootDim) {
                    walk_internal_topology(kInternalDim);
                } else {
                    add_memory(leaf_node_memory(layout_.value), "the tree's leaves");
                    const std::vector<uint64_t> leaf_mask =
                        read_mask(kLeafMaskBytes, layout_.leaf == LeafKind::Mask ? "a leaf's mask" : "a leaf's value mask");
                    leaf_active_.push_back(popcount(leaf_mask));
                }
            }
    }
    // A leaf's voxel buffer (LeafNode::readBuffers on a seekable stream: its value mask is stepped
    // over, the topology's mask says which values are stored).
    void walk_leaf_buffer(uint64_t active) {
        switch (layout_.leaf) {
        case LeafKind::Values:
            need(kLeafMaskBytes, "a leaf's value mask");
            pos_ += kLeafMaskBytes;
            walk_compressed_values(kLeafDim, active, layout_.value);
            break;
        case LeafKind::Bool:  // value mask, origin, value bits
            need(kLeafMaskBytes + 12 + kLeafMaskBytes, "a bool leaf's buffer");
            pos_ += kLeafMaskBytes + 12 + kLeafMaskBytes;
            break;
        case LeafKind::Mask:  // mask, origin
            need(kLeafMaskBytes + 12, "a mask leaf's buffer");
            pos_ += kLeafMaskBytes + 12;
            break;
        case LeafKind::Points: break;
        }
    }
    // io::readCompressedValues for `count` values, `active` of them active: a metadata byte, up to two
    // inactive values and a selection mask, then the stored values (only the active ones when the
    // grid is mask-compressed and the byte allows) as readData stores them.
    void walk_compressed_values(uint64_t count, uint64_t active, uint64_t value) {
        need(1, "a node's compression metadata");
        const uint8_t metadata = uint8_t(byte_at(pos_));
        pos_ += 1;
        if (metadata == kNoMaskAndOneInactiveVal || metadata == kMaskAndOneInactiveVal ||
            metadata == kMaskAndTwoInactiveVals) {
            const uint64_t n = metadata == kMaskAndTwoInactiveVals ? 2 : 1;
            need(n * value, "a node's inactive values");
            pos_ += n * value;
        }
        if (metadata == kMaskAndNoInactiveVals || metadata == kMaskAndOneInactiveVal ||
            metadata == kMaskAndTwoInactiveVals) {
            need(count / 8, "a node's selection mask");
            pos_ += count / 8;
        }
        const uint64_t stored = (compression_ & kCompressActiveMask) && metadata != kNoMaskAndAllVals ? active : count;
        // HalfReader reads nothing for no values; readData still reads a (zip or Blosc) chunk header.
        if (stored == 0 && from_half_) return;
        walk_data(stored * element_);
    }
    // io::readData: with Blosc or zip an int64 chunk size (<= 0: that many bytes stored raw, which
    // must be the expected size), else the raw values.
    void walk_data(uint64_t bytes) {
        if (!(compression_ & (kCompressBlosc | kCompressZip))) {
            need(bytes, "a node's values");
            pos_ += bytes;
            return;
        }
        const int64_t chunk = int64_t(read_u64("a compressed chunk's size"));
        if (chunk <= 0) {
            if (uint64_t(0) - uint64_t(chunk) != bytes)
                fail(fmt::format("an uncompressed chunk of {} bytes where {} are expected", uint64_t(0) - uint64_t(chunk),
                                 bytes));
            need(bytes, "an uncompressed chunk");
            pos_ += bytes;
            return;
        }
        need(uint64_t(chunk), "a compressed chunk");
        if (compression_ & kCompressBlosc) {
            // Blosc takes both sizes from its header: it would read past the chunk if its header said so.
            if (uint64_t(chunk) < kBloscHeaderBytes)
                fail(fmt::format("a {}-byte Blosc chunk (its header alone is {})", chunk, kBloscHeaderBytes));
            const uint32_t uncompressed = u32_at(pos_ + 4), compressed = u32_at(pos_ + 12);
            if (uncompressed != bytes || compressed != uint64_t(chunk))
                fail(fmt::format("a Blosc chunk's header declares {} bytes from {} ({} from {} expected)", uncompressed,
                                 compressed, bytes, chunk));
        }
        pos_ += uint64_t(chunk);
    }
    std::vector<uint64_t> read_mask(uint64_t bytes, const std::string& what) {
        need(bytes, what);
        std::vector<uint64_t> words(bytes / 8);
        read_at(pos_, reinterpret_cast<char*>(words.data()), bytes);
        pos_ += bytes;
        return words;
    }
    void add_memory(uint64_t bytes, const std::string& what) {
        memory_ += bytes;
        const uint64_t budget = memory_budget_bytes();
        if (budget > 0 && memory_ > budget)
            fail(fmt::format("the tree needs more than {} in memory ({} at {}), more than {}", format_bytes(memory_),
                             what, pos_, memory_budget_description()));
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
    // Returns the value of an "is_saved_as_half_float" entry (GridBase::saveFloatAsHalf), the last one.
    std::optional<bool> walk_metadata(const std::string& what) {
        std::optional<bool> saved_as_half;
        const uint32_t count = read_u32("entry count of " + what);
        // An entry is at least two empty strings and an empty value: 12 bytes.
        if (pos_ > size_ || count > (size_ - pos_) / 12)
            fail(fmt::format("{} declares {} entries in {} bytes", what, count, size_ - std::min(pos_, size_)));
        for (uint32_t i = 0; i < count; ++i) {
            const std::string name = read_string("metadata name");
            const std::string type = read_string("metadata type");
            const uint32_t n = read_u32("metadata size");
            need(n, "a metadata value");
            if (const std::optional<uint32_t> layout = vdb_metadata_layout_bytes(type); layout && *layout != n)
                fail(fmt::format("a \"{}\" metadata value declares {} bytes; OpenVDB reads {}", type, n, *layout));
            if (type == "__delayedload" && n > 0) walk_delayed_load(pos_, pos_ + n);
            if (name == "is_saved_as_half_float") {
                if (type != "bool") fail(fmt::format("is_saved_as_half_float metadata of type \"{}\" (bool expected)", type));
                saved_as_half = byte_at(pos_) != 0;
            }
            pos_ += n;
        }
        return saved_as_half;
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
            // OpenVDB's compression::bloscCompress pads arrays shorter than 128 bytes to 128.
            const uint32_t uncompressed = u32_at(at + 4), compressed = u32_at(at + 12);
            const bool padded = count * element < kBloscPadBytes && uncompressed == kBloscPadBytes;
            if ((uncompressed != count * element && !padded) || compressed != bytes)
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
    // The tree being walked: its layout, the grid's compression flags, the bytes of a stored value,
    // the memory OpenVDB will hold for its nodes, the active voxels of each leaf in topology order.
    TreeLayout layout_;
    uint32_t compression_ = 0;
    bool from_half_ = false;
    uint64_t element_ = 0;
    uint64_t memory_ = 0;
    std::vector<uint64_t> leaf_active_;
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
