#include "volguide/guiding/field_io.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "volguide/core/atomic_write.h"
#include "volguide/core/fnv1a.h"
#include "volguide/vmm/vmm_io.h"

namespace volguide {

namespace {

constexpr char kFieldMagic[8] = {'V', 'G', 'F', 'I', 'E', 'L', 'D', 0};
constexpr size_t kNodeBytes = 9;
constexpr uint32_t kOldestReadableVersion = 2;
// The smallest leaf record (an invalid leaf) of a format version.
size_t min_leaf_bytes(uint32_t version) { return version >= 3 ? 22 : 18; }

void put_u32(std::string& s, uint32_t v) {
    for (int i = 0; i < 4; ++i) s.push_back(char(uint8_t(v >> (8 * i))));
}
void put_f32(std::string& s, float v) {
    put_u32(s, std::bit_cast<uint32_t>(v));
}

// Sequential reader over the checksummed body with bounds checks.
struct Reader {
    const std::string& bytes;
    size_t pos, end;
    void need(size_t n, const char* what) const {
        if (end - pos < n) throw FieldFormatError(std::string("truncated guiding field (in ") + what + ")");
    }
    uint32_t u32(const char* what) {
        need(4, what);
        uint32_t v = 0;
        for (int i = 0; i < 4; ++i) v |= uint32_t(uint8_t(bytes[pos + i])) << (8 * i);
        pos += 4;
        return v;
    }
    float f32(const char* what) { return std::bit_cast<float>(u32(what)); }
    uint8_t u8(const char* what) {
        need(1, what);
        return uint8_t(bytes[pos++]);
    }
};

}  // namespace

std::string serialize_field(const GuidingField& field) {
    std::string s(kFieldMagic, sizeof(kFieldMagic));
    put_u32(s, kFieldFormatVersion);
    const BBox3f& b = field.tree().bounds();
    for (float v : {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z}) put_f32(s, v);
    const auto& nodes = field.tree().nodes();
    put_u32(s, uint32_t(nodes.size()));
    for (const SpatialTree::Node& n : nodes) {
        put_f32(s, n.split);
        put_u32(s, n.child);
        s.push_back(char(n.axis));
    }
    put_u32(s, uint32_t(field.leaves().size()));
    for (const GuidingLeaf& leaf : field.leaves()) {
        for (int c = 0; c < 3; ++c) put_f32(s, leaf.fluence[c]);
        put_u32(s, leaf.samples);
        put_f32(s, leaf.medium_fraction);
        s.push_back(char(leaf.valid ? 1 : 0));
        if (leaf.valid) {
            std::ostringstream vmm;
            write_vmm(vmm, leaf.vmm);
            s += vmm.str();
        }
        s.push_back(char(leaf.valid_indirect ? 1 : 0));
        if (leaf.valid_indirect) {
            std::ostringstream vmm;
            write_vmm(vmm, leaf.vmm_indirect);
            s += vmm.str();
        }
    }
    const uint64_t sum = fnv1a64(std::string_view(s).substr(sizeof(kFieldMagic)));
    put_u32(s, uint32_t(sum));
    put_u32(s, uint32_t(sum >> 32));
    return s;
}

namespace {

// Checks the magic, the version and the checksum; returns the version and the body's reader.
Reader open_body(const std::string& bytes, uint32_t& version) {
    if (bytes.size() < sizeof(kFieldMagic) + 8 || std::memcmp(bytes.data(), kFieldMagic, sizeof(kFieldMagic)) != 0)
        throw FieldFormatError("not a volguide guiding field (bad magic)");
    Reader header{bytes, sizeof(kFieldMagic), bytes.size()};
    version = header.u32("header");
    if (version < kOldestReadableVersion || version > kFieldFormatVersion)
        throw FieldFormatError("unsupported guiding field version " + std::to_string(version) +
                               " (this build reads " + std::to_string(kOldestReadableVersion) + " to " +
                               std::to_string(kFieldFormatVersion) + ")");
    const size_t body_end = bytes.size() - 8;
    Reader tail{bytes, body_end, bytes.size()};
    const uint64_t stored = uint64_t(tail.u32("checksum")) | uint64_t(tail.u32("checksum")) << 32;
    if (stored != fnv1a64(std::string_view(bytes).substr(sizeof(kFieldMagic), body_end - sizeof(kFieldMagic))))
        throw FieldFormatError("guiding field checksum mismatch (corrupt or truncated file)");
    return Reader{bytes, header.pos, body_end};
}

SpatialTree read_tree(Reader& r) {
    float box[6];
    for (float& v : box) {
        v = r.f32("bounds");
        if (!std::isfinite(v)) throw FieldFormatError("guiding field bounds are not finite");
    }
    const BBox3f bounds(Point3f(box[0], box[1], box[2]), Point3f(box[3], box[4], box[5]));
    const uint32_t node_count = r.u32("node count");
    r.need(size_t(node_count) * kNodeBytes, "nodes");
    std::vector<SpatialTree::Node> nodes(node_count);
    for (SpatialTree::Node& n : nodes) {
        n.split = r.f32("nodes");
        n.child = r.u32("nodes");
        n.axis = r.u8("nodes");
    }
    try {
        return SpatialTree::from_nodes(bounds, std::move(nodes));
    } catch (const std::invalid_argument& e) {
        throw FieldFormatError(std::string("invalid guiding field: ") + e.what());
    }
}

std::string leaf_error(uint32_t l, const std::string& what) {
    return "guiding field leaf " + std::to_string(l) + what;
}

bool read_flag(Reader& r, uint32_t l) {
    const uint8_t flag = r.u8("leaves");
    if (flag > 1) throw FieldFormatError(leaf_error(l, " has an invalid flag"));
    return flag == 1;
}

// Leaf l's VMM record, read in place from `vmm_in` (a stream over the whole file) at the reader's position.
void read_leaf_vmm(Reader& r, std::istringstream& vmm_in, uint32_t l, Vmm& vmm) {
    vmm_in.seekg(std::streamoff(r.pos));
    try {
        vmm = read_vmm<kVmmMaxLobes>(vmm_in);
    } catch (const VmmFormatError& e) {
        throw FieldFormatError(leaf_error(l, ": ") + e.what());
    }
    r.pos = size_t(vmm_in.tellg());
    if (r.pos > r.end) throw FieldFormatError("truncated guiding field (in leaf VMMs)");
    if (vmm.size() == 0) throw FieldFormatError(leaf_error(l, " is empty"));
}

void read_leaf(Reader& r, std::istringstream& vmm_in, uint32_t version, uint32_t l, GuidingLeaf& leaf) {
    for (int c = 0; c < 3; ++c) {
        leaf.fluence[c] = r.f32("leaves");
        if (!(leaf.fluence[c] >= 0.f) || !std::isfinite(leaf.fluence[c]))
            throw FieldFormatError(leaf_error(l, " has an invalid fluence"));
    }
    leaf.samples = r.u32("leaves");
    if (version >= 3) {
        leaf.medium_fraction = r.f32("leaves");
        if (!(leaf.medium_fraction <= 1.f) || std::isnan(leaf.medium_fraction))
            throw FieldFormatError(leaf_error(l, " has an invalid medium fraction"));
        if (leaf.medium_fraction < 0.f) leaf.medium_fraction = -1.f;
    }
    leaf.valid = read_flag(r, l);
    if (leaf.valid) read_leaf_vmm(r, vmm_in, l, leaf.vmm);
    leaf.valid_indirect = read_flag(r, l);
    if (leaf.valid_indirect) read_leaf_vmm(r, vmm_in, l, leaf.vmm_indirect);
}

}  // namespace

GuidingField deserialize_field(const std::string& bytes) {
    uint32_t version = 0;
    Reader r = open_body(bytes, version);
    SpatialTree tree = read_tree(r);
    const uint32_t leaf_count = r.u32("leaf count");
    if (int64_t(leaf_count) != tree.leaf_count())
        throw FieldFormatError("guiding field has " + std::to_string(leaf_count) + " leaves, its tree " +
                               std::to_string(tree.leaf_count()));
    r.need(size_t(leaf_count) * min_leaf_bytes(version), "leaves");
    std::vector<GuidingLeaf> leaves(leaf_count);
    std::istringstream vmm_in(bytes);  // VMM records are read in place
    for (uint32_t l = 0; l < leaf_count; ++l) read_leaf(r, vmm_in, version, l, leaves[l]);
    if (r.pos != r.end) throw FieldFormatError("guiding field has trailing data");
    return GuidingField(std::move(tree), std::move(leaves));
}

void save_field(const std::string& path, const GuidingField& field) {
    const std::string bytes = serialize_field(field);
    const std::string error = write_atomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out.write(bytes.data(), std::streamsize(bytes.size()));
        out.close();
        if (!out) throw std::runtime_error("write failed");
    });
    if (!error.empty()) throw FieldFormatError("\"" + path + "\": cannot write the guiding field: " + error);
}

GuidingField load_field(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FieldFormatError("\"" + path + "\": cannot open the guiding field");
    std::ostringstream buf;
    buf << in.rdbuf();
    try {
        return deserialize_field(buf.str());
    } catch (const FieldFormatError& e) {
        throw FieldFormatError("\"" + path + "\": " + e.what());
    }
}

}  // namespace volguide
