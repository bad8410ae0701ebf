#pragma once
// Writes Mitsuba `.serialized` meshes (the layout read by geometry/shapes/serialized_reader.cpp) for
// the reader's unit tests and the fuzz seeds: one or more shapes, each a header and a zlib stream,
// and the table of shape offsets at the end.
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace volguide::test {

struct SerializedShape {
    std::vector<float> positions;  // 3 per vertex
    std::vector<float> normals;    // 3 per vertex or empty
    std::vector<float> uvs;        // 2 per vertex or empty
    std::vector<uint32_t> indices;
    bool double_precision = false;
    bool face_normals = false;
    std::string name = "shape";
    // Overrides of the counts the stream declares (to write inconsistent files); -1: the real ones.
    int64_t vertex_count = -1, triangle_count = -1;
};

template <typename T>
void serialized_put(std::string& out, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));  // little endian hosts only, as the reader
    out.append(b, sizeof(T));
}

inline void serialized_put_scalars(std::string& out, const std::vector<float>& v, bool dbl) {
    for (float x : v) dbl ? serialized_put<double>(out, x) : serialized_put<float>(out, x);
}

// The uncompressed stream of one shape.
inline std::string serialized_stream(const SerializedShape& s, int version) {
    std::string raw;
    uint32_t flags = s.double_precision ? 0x2000u : 0x1000u;
    if (!s.normals.empty()) flags |= 0x0001u;
    if (!s.uvs.empty()) flags |= 0x0002u;
    if (s.face_normals) flags |= 0x0010u;
    serialized_put<uint32_t>(raw, flags);
    if (version == 4) raw.append(s.name.c_str(), s.name.size() + 1);
    serialized_put<uint64_t>(raw, s.vertex_count >= 0 ? uint64_t(s.vertex_count) : s.positions.size() / 3);
    serialized_put<uint64_t>(raw, s.triangle_count >= 0 ? uint64_t(s.triangle_count) : s.indices.size() / 3);
    serialized_put_scalars(raw, s.positions, s.double_precision);
    serialized_put_scalars(raw, s.normals, s.double_precision);
    serialized_put_scalars(raw, s.uvs, s.double_precision);
    for (uint32_t i : s.indices) serialized_put<uint32_t>(raw, i);
    return raw;
}

inline std::string serialized_file(const std::vector<SerializedShape>& shapes, int version = 4) {
    std::string out;
    std::vector<uint64_t> offsets;
    for (const SerializedShape& s : shapes) {
        offsets.push_back(out.size());
        serialized_put<uint16_t>(out, 0x041C);
        serialized_put<uint16_t>(out, uint16_t(version));
        const std::string raw = serialized_stream(s, version);
        uLongf size = compressBound(uLong(raw.size()));
        std::string packed(size, '\0');
        if (compress(reinterpret_cast<Bytef*>(packed.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
                     uLong(raw.size())) != Z_OK)
            throw std::runtime_error("zlib compress failed");
        out.append(packed.data(), size);
    }
    for (uint64_t o : offsets) version == 4 ? serialized_put<uint64_t>(out, o) : serialized_put<uint32_t>(out, uint32_t(o));
    serialized_put<uint32_t>(out, uint32_t(shapes.size()));
    return out;
}

// The quad [-1,1]^2 at z = 0 (two triangles), with normals and uvs.
inline SerializedShape serialized_quad(float z = 0.f) {
    SerializedShape s;
    s.positions = {-1, -1, z, 1, -1, z, 1, 1, z, -1, 1, z};
    s.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    s.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
    s.indices = {0, 1, 2, 2, 3, 0};
    return s;
}

}  // namespace volguide::test
