// OBJ reading through tinyobjloader (v2 API), without its triangulation so that polygons are
// split as a fan around their first vertex exactly like Mitsuba's loader.
#include <tiny_obj_loader.h>

#include <filesystem>
#include <unordered_map>

#include "volguide/geometry/shapes/mesh_files.h"

namespace volguide {

namespace {

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

// The mesh's vertices, each added the first time its index triple is referenced.
class ObjVertices {
  public:
    ObjVertices(const tinyobj::attrib_t& attrib, bool flip_tex_coords, const std::string& path,
                const SourceLocation& loc, TriangleMesh& mesh)
        : attrib_(attrib), flip_tex_coords_(flip_tex_coords), path_(path), loc_(loc), mesh_(mesh) {
        vertex_of_.reserve(nv_);
    }

    uint32_t id(const tinyobj::index_t& idx) {
        Triple key{idx.vertex_index, idx.texcoord_index, idx.normal_index};
        auto [it, inserted] = vertex_of_.try_emplace(key, uint32_t(mesh_.positions.size()));
        if (!inserted) return it->second;
        if (idx.vertex_index < 0 || size_t(idx.vertex_index) >= nv_)
            fail(loc_, "error while loading OBJ file \"{}\": reference to invalid vertex {}", path_,
                 idx.vertex_index + 1);
        const float* v = &attrib_.vertices[3 * size_t(idx.vertex_index)];
        mesh_.positions.emplace_back(v[0], v[1], v[2]);
        if (nt_ > 0) mesh_.uvs.push_back(uv(idx.texcoord_index));
        if (nn_ > 0) mesh_.normals.push_back(normal(idx.normal_index));
        return it->second;
    }

  private:
    Vec2f uv(int index) const {
        if (index < 0) return Vec2f(0.f, 0.f);
        if (size_t(index) >= nt_)
            fail(loc_, "error while loading OBJ file \"{}\": reference to invalid texture coordinate {}",
                 path_, index + 1);
        const float* t = &attrib_.texcoords[2 * size_t(index)];
        return {t[0], flip_tex_coords_ ? 1.f - t[1] : t[1]};
    }
    Normal3f normal(int index) const {
        if (index < 0) return Normal3f(0.f);
        if (size_t(index) >= nn_)
            fail(loc_, "error while loading OBJ file \"{}\": reference to invalid normal {}", path_,
                 index + 1);
        const float* p = &attrib_.normals[3 * size_t(index)];
        return Normal3f(p[0], p[1], p[2]);
    }

    const tinyobj::attrib_t& attrib_;
    const size_t nv_ = attrib_.vertices.size() / 3, nn_ = attrib_.normals.size() / 3,
                 nt_ = attrib_.texcoords.size() / 2;
    bool flip_tex_coords_;
    const std::string& path_;
    const SourceLocation& loc_;
    TriangleMesh& mesh_;
    std::unordered_map<Triple, uint32_t, TripleHash> vertex_of_;
};

}  // namespace

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
    TriangleMesh mesh;
    ObjVertices vertices(reader.GetAttrib(), flip_tex_coords, path, loc, mesh);
    // Polygons as a fan around their first vertex.
    for (const auto& shape : reader.GetShapes()) {
        size_t offset = 0;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            size_t count = shape.mesh.num_face_vertices[f];
            if (count >= 3) {
                uint32_t first = vertices.id(shape.mesh.indices[offset]);
                uint32_t prev = vertices.id(shape.mesh.indices[offset + 1]);
                for (size_t k = 2; k < count; ++k) {
                    uint32_t cur = vertices.id(shape.mesh.indices[offset + k]);
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
