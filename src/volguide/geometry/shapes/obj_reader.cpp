// OBJ reading through tinyobjloader (v2 API), without its triangulation so that polygons are
// split as a fan around their first vertex exactly like Mitsuba's loader.
#include <tiny_obj_loader.h>

#include <filesystem>
#include <unordered_map>

#include "volguide/geometry/shapes/mesh_files.h"

namespace volguide {

TriangleMesh read_obj(const std::string& path, bool flip_tex_coords, const SourceLocation& loc) {
    tinyobj::ObjReaderConfig config;
    config.triangulate = false;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config)) {
        std::string err = reader.Error();
        while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
        fail(loc, "error while loading OBJ file \"{}\": {}", path, err.empty() ? "unknown error" : err);
    }
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    const size_t nv = attrib.vertices.size() / 3, nn = attrib.normals.size() / 3,
                 nt = attrib.texcoords.size() / 2;

    TriangleMesh mesh;
    const bool has_normals = nn > 0, has_uvs = nt > 0;
    // One vertex per distinct (position, texcoord, normal) index triple; -1 = absent.
    struct Triple {
        int v, t, n;
        bool operator==(const Triple&) const = default;
    };
    struct TripleHash {
        size_t operator()(const Triple& k) const {
            uint64_t h = uint64_t(uint32_t(k.v)) * 0x9E3779B97F4A7C15ULL;
            h ^= (uint64_t(uint32_t(k.t)) + 0x632BE59BD9B4E019ULL + (h << 6) + (h >> 2));
            h ^= (uint64_t(uint32_t(k.n)) + 0x94D049BB133111EBULL + (h << 6) + (h >> 2));
            return size_t(h);
        }
    };
    std::unordered_map<Triple, uint32_t, TripleHash> vertex_of;
    vertex_of.reserve(nv);
    auto vertex_id = [&](const tinyobj::index_t& idx) -> uint32_t {
        Triple key{idx.vertex_index, idx.texcoord_index, idx.normal_index};
        auto [it, inserted] = vertex_of.try_emplace(key, uint32_t(mesh.positions.size()));
        if (!inserted) return it->second;
        if (idx.vertex_index < 0 || size_t(idx.vertex_index) >= nv)
            fail(loc, "error while loading OBJ file \"{}\": reference to invalid vertex {}", path,
                 idx.vertex_index + 1);
        const float* v = &attrib.vertices[3 * size_t(idx.vertex_index)];
        mesh.positions.emplace_back(v[0], v[1], v[2]);
        if (has_uvs) {
            Vec2f uv(0.f, 0.f);
            if (idx.texcoord_index >= 0) {
                if (size_t(idx.texcoord_index) >= nt)
                    fail(loc,
                         "error while loading OBJ file \"{}\": reference to invalid texture coordinate {}",
                         path, idx.texcoord_index + 1);
                const float* t = &attrib.texcoords[2 * size_t(idx.texcoord_index)];
                uv = {t[0], flip_tex_coords ? 1.f - t[1] : t[1]};
            }
            mesh.uvs.push_back(uv);
        }
        if (has_normals) {
            Normal3f n(0.f);
            if (idx.normal_index >= 0) {
                if (size_t(idx.normal_index) >= nn)
                    fail(loc, "error while loading OBJ file \"{}\": reference to invalid normal {}", path,
                         idx.normal_index + 1);
                const float* p = &attrib.normals[3 * size_t(idx.normal_index)];
                n = Normal3f(p[0], p[1], p[2]);
            }
            mesh.normals.push_back(n);
        }
        return it->second;
    };

    for (const auto& shape : reader.GetShapes()) {
        size_t offset = 0;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            size_t count = shape.mesh.num_face_vertices[f];
            if (count >= 3) {
                uint32_t first = vertex_id(shape.mesh.indices[offset]);
                uint32_t prev = vertex_id(shape.mesh.indices[offset + 1]);
                for (size_t k = 2; k < count; ++k) {
                    uint32_t cur = vertex_id(shape.mesh.indices[offset + k]);
                    mesh.indices.insert(mesh.indices.end(), {first, prev, cur});
                    prev = cur;
                }
            }
            offset += count;
        }
    }
    return mesh;
}

std::string resolve_filename(const Properties& props, const std::string& name) {
    namespace fs = std::filesystem;
    std::string filename = props.get_string(name);
    fs::path p(filename);
    if (fs::exists(p)) return p.string();
    if (p.is_relative()) {
        fs::path scene_dir = fs::path(props.location_of(name).file).parent_path();
        fs::path candidate = scene_dir / p;
        if (!scene_dir.empty() && fs::exists(candidate)) return candidate.string();
    }
    props.fail_at(name, "{} '{}': file \"{}\" not found", props.category(), props.type(), filename);
}

}  // namespace volguide
