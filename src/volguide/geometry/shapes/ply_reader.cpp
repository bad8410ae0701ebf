// A small Stanford PLY reader (Debian has no PLY library). Reads the whole file, parses the
// header, then walks every element in order (ascii tokens or packed binary of either byte
// order); vertex positions/normals/uvs, face index lists and Mitsuba 3's mesh attributes are kept.
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

#include "volguide/geometry/shapes/mesh_files.h"

namespace volguide {

namespace {

enum class Format { Ascii, BinaryLE, BinaryBE };
enum class Type { I8, U8, I16, U16, I32, U32, F32, F64 };

struct Property {
    std::string name;
    Type type = Type::F32;
    bool is_list = false;
    Type count_type = Type::U8;
};

struct Element {
    std::string name;
    size_t count = 0;
    std::vector<Property> props;
};

struct PlyError {
    std::string what;
};

[[noreturn]] void ply_fail(std::string what) {
    throw PlyError{std::move(what)};
}

bool parse_type(const std::string& s, Type& t) {
    static const std::pair<const char*, Type> names[] = {
        {"char", Type::I8},   {"int8", Type::I8},     {"uchar", Type::U8},   {"uint8", Type::U8},
        {"short", Type::I16}, {"int16", Type::I16},   {"ushort", Type::U16}, {"uint16", Type::U16},
        {"int", Type::I32},   {"int32", Type::I32},   {"uint", Type::U32},   {"uint32", Type::U32},
        {"float", Type::F32}, {"float32", Type::F32}, {"double", Type::F64}, {"float64", Type::F64}};
    for (const auto& [name, type] : names)
        if (s == name) {
            t = type;
            return true;
        }
    return false;
}

// Sequential reader over the body of the file.
class BodyReader {
  public:
    BodyReader(const std::string& data, size_t pos, Format fmt) : data_(data), pos_(pos), fmt_(fmt) {}

    double read(Type t) { return fmt_ == Format::Ascii ? read_ascii(t) : read_binary(t); }

    // A list's length. Every entry takes at least one byte in any format, so a length beyond the
    // bytes left is rejected before anything loops over or stores it (the count may be a float or
    // negative in a malformed file, and converting those to size_t is undefined).
    size_t read_count(const Property& p) {
        const double n = read(p.count_type);
        if (!(n >= 0.0) || n != std::floor(n) || n > double(data_.size() - pos_))
            ply_fail(fmt::format("invalid length {} of the list property '{}'", n, p.name));
        return size_t(n);
    }

    void finish() {
        if (fmt_ != Format::Ascii) return;
        skip_space();
        if (pos_ < data_.size()) ply_fail("unexpected data after the last element");
    }

  private:
    void skip_space() {
        while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
    }
    double read_ascii(Type t) {
        skip_space();
        if (pos_ >= data_.size()) ply_fail("unexpected end of file");
        const char* begin = data_.data() + pos_;
        const char* end = data_.data() + data_.size();
        if (*begin == '+') ++begin;  // from_chars does not accept an explicit plus sign
        double v;
        auto [ptr, ec] = std::from_chars(begin, end, v);
        if (ec != std::errc() || (ptr < end && !std::isspace(static_cast<unsigned char>(*ptr)))) {
            const char* tok_end = begin;
            while (tok_end < end && !std::isspace(static_cast<unsigned char>(*tok_end))) ++tok_end;
            ply_fail(fmt::format("could not parse the value \"{}\"",
                                 std::string_view(begin, size_t(tok_end - begin))));
        }
        pos_ = size_t(ptr - data_.data());
        return v;
    }
    template <typename T>
    T load() {
        if (pos_ + sizeof(T) > data_.size()) ply_fail("unexpected end of file");
        unsigned char bytes[sizeof(T)];
        std::memcpy(bytes, data_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        bool file_le = fmt_ == Format::BinaryLE;
        if (file_le != (std::endian::native == std::endian::little))
            for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
        T v;
        std::memcpy(&v, bytes, sizeof(T));
        return v;
    }
    double read_binary(Type t) {
        switch (t) {
            case Type::I8:
                return load<int8_t>();
            case Type::U8:
                return load<uint8_t>();
            case Type::I16:
                return load<int16_t>();
            case Type::U16:
                return load<uint16_t>();
            case Type::I32:
                return load<int32_t>();
            case Type::U32:
                return load<uint32_t>();
            case Type::F32:
                return load<float>();
            case Type::F64:
                return load<double>();
        }
        return 0.0;
    }

    const std::string& data_;
    size_t pos_;
    Format fmt_;
};

// Returns the header's elements and the offset of the body.
std::vector<Element> parse_header(const std::string& data, Format& fmt, size_t& body) {
    std::vector<Element> elements;
    size_t pos = 0;
    bool first = true, have_format = false;
    while (true) {
        size_t eol = data.find('\n', pos);
        if (eol == std::string::npos) ply_fail("header is not terminated by 'end_header'");
        std::string line = data.substr(pos, eol - pos);
        pos = eol + 1;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream iss(line);
        std::string token;
        if (first) {
            if (!(iss >> token) || token != "ply") ply_fail("not a PLY file (missing 'ply' magic)");
            first = false;
            continue;
        }
        if (!(iss >> token)) continue;
        if (token == "comment" || token == "obj_info") continue;
        if (token == "format") {
            std::string kind, version;
            iss >> kind >> version;
            if (kind == "ascii")
                fmt = Format::Ascii;
            else if (kind == "binary_little_endian")
                fmt = Format::BinaryLE;
            else if (kind == "binary_big_endian")
                fmt = Format::BinaryBE;
            else
                ply_fail(fmt::format("invalid format '{}'", kind));
            if (version != "1.0") ply_fail(fmt::format("unsupported PLY version '{}'", version));
            have_format = true;
        } else if (token == "element") {
            Element e;
            long long count = -1;
            if (!(iss >> e.name >> count) || count < 0)
                ply_fail(fmt::format("malformed header line \"{}\"", line));
            e.count = size_t(count);
            elements.push_back(std::move(e));
        } else if (token == "property") {
            if (elements.empty()) ply_fail("'property' before any 'element' in the header");
            Property p;
            std::string type;
            if (!(iss >> type)) ply_fail(fmt::format("malformed header line \"{}\"", line));
            if (type == "list") {
                std::string count_type, item_type;
                p.is_list = true;
                if (!(iss >> count_type >> item_type >> p.name) || !parse_type(count_type, p.count_type) ||
                    !parse_type(item_type, p.type))
                    ply_fail(fmt::format("malformed header line \"{}\"", line));
            } else if (!parse_type(type, p.type) || !(iss >> p.name)) {
                ply_fail(fmt::format("malformed header line \"{}\"", line));
            }
            elements.back().props.push_back(std::move(p));
        } else if (token == "end_header") {
            break;
        } else {
            ply_fail(fmt::format("unknown header keyword '{}'", token));
        }
    }
    if (!have_format) ply_fail("missing 'format' line in the header");
    body = pos;
    return elements;
}

// Element counts come from the header; each entry of an element with properties takes at least one
// byte, so a count beyond the body's size is a malformed file, reported before any allocation.
void check_counts_fit(const std::vector<Element>& elements, size_t body_bytes) {
    for (const Element& e : elements)
        if (!e.props.empty() && e.count > body_bytes)
            ply_fail(fmt::format("element '{}' declares {} entries but only {} bytes follow the header", e.name,
                                 e.count, body_bytes));
}

int find_prop(const Element& e, std::initializer_list<const char*> names) {
    for (const char* n : names)
        for (size_t i = 0; i < e.props.size(); ++i)
            if (e.props[i].name == n && !e.props[i].is_list) return int(i);
    return -1;
}

// The texture coordinates' properties under the first of the usual name pairs the element has both of.
std::pair<int, int> find_uv_props(const Element& e) {
    int iu = -1, iv = -1;
    const std::pair<const char*, const char*> uv_names[] = {
        {"u", "v"}, {"texture_u", "texture_v"}, {"s", "t"}, {"texture_s", "texture_t"}};
    for (const auto& [un, vn] : uv_names)
        if (iu < 0 || iv < 0) {
            iu = find_prop(e, {un});
            iv = find_prop(e, {vn});
        }
    return {iu, iv};
}

// ---- mesh attributes (Mitsuba 3's PLY naming) --------------------------------------------------
// Consecutive scalar properties `{prefix}_{c}` whose suffixes run through one column of the table
// below (x y z w | r g b a | 0 1 2 3 | 1 2 3 4) form the attribute "{element}_{prefix}" (the r g b
// column adds "_color"); r g b / red green blue without a prefix form "{element}_color". Only 1 and
// 3 channels are kept (Mitsuba ignores the other counts); integer properties are read as numbers,
// not normalised (as Mitsuba).
struct AttributeGroup {
    std::string name;
    std::vector<int> props;  // property indices, one per channel
};

constexpr const char* kAttributeSuffixes[4] = {"xr01", "yg12", "zb23", "wa34"};

std::vector<AttributeGroup> color_without_prefix(const Element& e, const std::string& element,
                                                 std::vector<bool>& taken) {
    for (auto names : {std::array<const char*, 3>{"r", "g", "b"}, std::array<const char*, 3>{"red", "green", "blue"}}) {
        AttributeGroup g{element + "_color", {}};
        for (const char* n : names) g.props.push_back(find_prop(e, {n}));
        if (g.props[0] < 0 || g.props[1] < 0 || g.props[2] < 0) continue;
        for (int k : g.props) taken[size_t(k)] = true;
        for (const char* alpha : {"a", "alpha"})
            if (int ia = find_prop(e, {alpha}); ia >= 0) taken[size_t(ia)] = true;  // alpha is not read
        return {g};
    }
    return {};
}

// Splits "prefix_c" into its prefix and one-character suffix; false for other names.
bool split_attribute_name(const std::string& name, std::string& prefix, char& suffix) {
    const size_t pos = name.find_last_of('_');
    if (pos == std::string::npos || pos == 0 || pos + 2 != name.size()) return false;
    prefix = name.substr(0, pos);
    suffix = name[pos + 1];
    return true;
}

void flush_group(AttributeGroup& g, int column, std::vector<AttributeGroup>& out) {
    if (g.props.size() == 1 || g.props.size() == 3) {
        if (column == 1) g.name += "_color";
        out.push_back(g);
    }
    g = AttributeGroup{};
}

std::vector<AttributeGroup> attribute_groups(const Element& e, const std::string& element,
                                             std::vector<bool> taken) {
    std::vector<AttributeGroup> out = color_without_prefix(e, element, taken);
    AttributeGroup cur;
    std::string cur_prefix;
    int column = -1;
    for (size_t k = 0; k < e.props.size(); ++k) {
        std::string prefix;
        char suffix = 0;
        const bool named = !taken[k] && !e.props[k].is_list && split_attribute_name(e.props[k].name, prefix, suffix);
        if (!cur.props.empty() && (!named || prefix != cur_prefix ||
                                   cur.props.size() >= 4 || suffix != kAttributeSuffixes[cur.props.size()][column]))
            flush_group(cur, column, out);
        if (!named) continue;
        if (cur.props.empty()) {
            const char* first = std::strchr(kAttributeSuffixes[0], suffix);
            if (!first) continue;
            column = int(first - kAttributeSuffixes[0]);
            cur_prefix = prefix;
            cur.name = element + "_" + prefix;
        }
        cur.props.push_back(int(k));
    }
    if (!cur.props.empty()) flush_group(cur, column, out);
    return out;
}

std::vector<MeshAttribute> start_attributes(const std::vector<AttributeGroup>& groups, size_t count) {
    std::vector<MeshAttribute> attrs;
    for (const AttributeGroup& g : groups) {
        MeshAttribute a{g.name, int(g.props.size()), {}};
        a.values.reserve(count * g.props.size());
        attrs.push_back(std::move(a));
    }
    return attrs;
}

void append_attributes(const std::vector<AttributeGroup>& groups, const std::vector<double>& values,
                       std::vector<MeshAttribute>& attrs) {
    for (size_t i = 0; i < groups.size(); ++i)
        for (int k : groups[i].props) attrs[i].values.push_back(float(values[size_t(k)]));
}

void read_vertices(BodyReader& reader, const Element& e, TriangleMesh& mesh) {
    std::vector<double> values(e.props.size(), 0.0);
    int ix = find_prop(e, {"x"}), iy = find_prop(e, {"y"}), iz = find_prop(e, {"z"});
    if (ix < 0 || iy < 0 || iz < 0) ply_fail("vertex element lacks x, y or z");
    int inx = find_prop(e, {"nx"}), iny = find_prop(e, {"ny"}), inz = find_prop(e, {"nz"});
    bool normals = inx >= 0 && iny >= 0 && inz >= 0;
    const auto [iu, iv] = find_uv_props(e);
    bool uvs = iu >= 0 && iv >= 0;
    std::vector<bool> taken(e.props.size(), false);
    for (int k : {ix, iy, iz, inx, iny, inz, iu, iv})
        if (k >= 0) taken[size_t(k)] = true;
    const std::vector<AttributeGroup> groups = attribute_groups(e, "vertex", taken);
    std::vector<MeshAttribute> attrs = start_attributes(groups, e.count);
    mesh.positions.reserve(e.count + 1);
    for (size_t i = 0; i < e.count; ++i) {
        for (size_t k = 0; k < e.props.size(); ++k) {
            const Property& p = e.props[k];
            if (p.is_list) {
                size_t n = reader.read_count(p);
                for (size_t j = 0; j < n; ++j) reader.read(p.type);
            } else {
                values[k] = reader.read(p.type);
            }
        }
        mesh.positions.emplace_back(float(values[ix]), float(values[iy]), float(values[iz]));
        if (normals) mesh.normals.emplace_back(float(values[inx]), float(values[iny]), float(values[inz]));
        if (uvs) mesh.uvs.emplace_back(float(values[iu]), float(values[iv]));
        append_attributes(groups, values, attrs);
    }
    for (MeshAttribute& a : attrs) mesh.attributes.push_back(std::move(a));
}

// Face `face`'s index list of n entries: a triangle, or a quad split along its 0-2 diagonal.
void read_face_indices(BodyReader& reader, const Property& p, size_t face, size_t n, TriangleMesh& mesh) {
    if (n != 3 && n != 4)
        ply_fail(fmt::format("face {} has {} vertices (only triangles and quads are supported)", face, n));
    uint32_t idx[4];
    for (size_t j = 0; j < n; ++j) {
        double v = reader.read(p.type);
        if (!(v >= 0.0) || v >= 4294967295.0)
            ply_fail(fmt::format("face {} has an invalid vertex index {}", face, v));
        idx[j] = uint32_t(v);
    }
    mesh.indices.insert(mesh.indices.end(), {idx[0], idx[1], idx[2]});
    if (n == 4) mesh.indices.insert(mesh.indices.end(), {idx[0], idx[2], idx[3]});
}

void read_faces(BodyReader& reader, const Element& e, TriangleMesh& mesh) {
    int list = -1;
    for (const char* name : {"vertex_indices", "vertex_index"})
        for (size_t k = 0; k < e.props.size() && list < 0; ++k)
            if (e.props[k].is_list && e.props[k].name == name) list = int(k);
    if (list < 0) ply_fail("face element has no vertex_indices/vertex_index list");
    const std::vector<AttributeGroup> groups = attribute_groups(e, "face", std::vector<bool>(e.props.size(), false));
    std::vector<MeshAttribute> attrs = start_attributes(groups, e.count);
    std::vector<double> values(e.props.size(), 0.0);
    mesh.indices.reserve(3 * e.count + 1);
    for (size_t i = 0; i < e.count; ++i) {
        const size_t triangles_before = mesh.triangle_count();
        for (size_t k = 0; k < e.props.size(); ++k) {
            const Property& p = e.props[k];
            if (!p.is_list) {
                values[k] = reader.read(p.type);
                continue;
            }
            size_t n = reader.read_count(p);
            if (int(k) != list) {
                for (size_t j = 0; j < n; ++j) reader.read(p.type);
                continue;
            }
            read_face_indices(reader, p, i, n, mesh);
        }
        // A quad split in two gives both triangles its values.
        for (size_t t = triangles_before; t < mesh.triangle_count(); ++t) append_attributes(groups, values, attrs);
    }
    for (MeshAttribute& a : attrs) mesh.attributes.push_back(std::move(a));
}

// Entries without properties hold no bytes (their count is not bounded by the file: a fuzzed
// header's 8.9e15 of them took this loop minutes to skip), so only elements with properties are read.
void skip_element(BodyReader& reader, const Element& e) {
    if (e.props.empty()) return;
    for (size_t i = 0; i < e.count; ++i)
        for (const Property& p : e.props) {
            size_t n = p.is_list ? reader.read_count(p) : 1;
            for (size_t j = 0; j < n; ++j) reader.read(p.type);
        }
}

TriangleMesh parse_ply(const std::string& data) {
    TriangleMesh mesh;
    Format fmt = Format::Ascii;
    size_t body = 0;
    std::vector<Element> elements = parse_header(data, fmt, body);
    check_counts_fit(elements, data.size() - body);
    BodyReader reader(data, body, fmt);
    bool have_vertices = false, have_faces = false;
    for (const Element& e : elements) {
        if (e.name == "vertex") {
            read_vertices(reader, e, mesh);
            have_vertices = true;
        } else if (e.name == "face") {
            read_faces(reader, e, mesh);
            have_faces = true;
        } else {
            skip_element(reader, e);
        }
    }
    reader.finish();
    if (!have_vertices) ply_fail("no vertex element");
    if (!have_faces) ply_fail("no face element");
    for (uint32_t i : mesh.indices)
        if (i >= mesh.positions.size())
            ply_fail(
                fmt::format("a face refers to vertex {} but there are only {}", i, mesh.positions.size()));
    return mesh;
}

}  // namespace

TriangleMesh read_ply(const std::string& path, const SourceLocation& loc) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(loc, "error while loading PLY file \"{}\": cannot open the file", path);
    std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    try {
        return parse_ply(data);
    } catch (const PlyError& e) {
        fail(loc, "error while loading PLY file \"{}\": {}", path, e.what);
    }
}

}  // namespace volguide
