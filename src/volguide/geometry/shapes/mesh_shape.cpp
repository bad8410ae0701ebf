#include "volguide/geometry/shapes/mesh_shape.h"

#include <cmath>
#include <vector>

#include "volguide/core/warp.h"
#include "volguide/geometry/surface_frame.h"

namespace volguide {

MeshOptions read_mesh_options(const Properties& props, bool accepts_face_normals) {
    MeshOptions o;
    o.to_world = props.get_transform("to_world");
    if (accepts_face_normals) o.face_normals = props.get_bool("face_normals", false);
    o.flip_normals = props.get_bool("flip_normals", false);
    return o;
}

void transform_mesh(TriangleMesh& mesh, const Transform& to_world) {
    if (to_world.is_identity()) return;
    for (auto& p : mesh.positions) p = to_world.apply_point(p);
    for (auto& n : mesh.normals) {
        Normal3f tn = to_world.apply_normal(n);
        float len = norm(tn);
        n = len > 0.f ? tn / len : tn;
    }
}

namespace {
// Angle between two unit vectors, accurate for small and large angles (Mitsuba's unit_angle).
float unit_angle(const Vec3f& a, const Vec3f& b) {
    float d = dot(a, b);
    if (d < 0.f) return Pi - 2.f * safe_asin(0.5f * norm(a + b));
    return 2.f * safe_asin(0.5f * norm(b - a));
}
}  // namespace

void compute_vertex_normals(TriangleMesh& mesh) {
    std::vector<Normal3f> acc(mesh.positions.size(), Normal3f(0.f));
    for (size_t f = 0; f < mesh.triangle_count(); ++f) {
        const uint32_t* idx = &mesh.indices[3 * f];
        Point3f v[3] = {mesh.positions[idx[0]], mesh.positions[idx[1]], mesh.positions[idx[2]]};
        Normal3f n = cross(v[1] - v[0], v[2] - v[0]);
        float len2 = squared_norm(n);
        if (!(len2 > 0.f)) continue;
        n = n / std::sqrt(len2);
        for (int j = 0; j < 3; ++j) {
            Vec3f e1 = v[(j + 1) % 3] - v[j], e2 = v[(j + 2) % 3] - v[j];
            float l1 = norm(e1), l2 = norm(e2);
            if (l1 == 0.f || l2 == 0.f) continue;
            acc[idx[j]] += n * unit_angle(e1 / l1, e2 / l2);
        }
    }
    for (auto& n : acc) {
        float len = norm(n);
        n = len > 0.f ? n / len : Normal3f(1.f, 0.f, 0.f);  // isolated vertex: arbitrary (as Mitsuba)
    }
    mesh.normals = std::move(acc);
}

MeshShape::MeshShape(const Properties& props, TriangleMesh mesh, const MeshOptions& opts, std::string name,
                     bool compute_missing_normals)
    : mesh_(std::move(mesh)), flip_normals_(opts.flip_normals), name_(std::move(name)) {
    const size_t nv = mesh_.positions.size();
    if (mesh_.indices.empty()) props.fail_here("mesh \"{}\" contains no triangles", name_);
    if (mesh_.indices.size() % 3 != 0)
        props.fail_here("mesh \"{}\": index count is not a multiple of 3", name_);
    for (uint32_t i : mesh_.indices)
        if (i >= nv)
            props.fail_here("mesh \"{}\": face refers to vertex {} but there are only {}", name_, i, nv);
    if (!mesh_.normals.empty() && mesh_.normals.size() != nv)
        props.fail_here("mesh \"{}\": normal count differs from vertex count", name_);
    if (!mesh_.uvs.empty() && mesh_.uvs.size() != nv)
        props.fail_here("mesh \"{}\": texture coordinate count differs from vertex count", name_);

    check_attributes(props);

    transform_mesh(mesh_, opts.to_world);
    for (const auto& p : mesh_.positions) {
        if (!all_finite(p)) props.fail_here("mesh \"{}\" contains invalid vertex positions", name_);
        bbox_.expand(p);
    }
    if (opts.face_normals)
        mesh_.normals.clear();
    else if (mesh_.normals.empty() && compute_missing_normals)
        compute_vertex_normals(mesh_);

    // Embree reads vertex buffers with 16-byte loads: keep one spare element of capacity so the
    // acceleration structure can share the buffer instead of copying it.
    mesh_.positions.reserve(nv + 1);
    mesh_.indices.reserve(mesh_.indices.size() + 1);

    std::vector<float> areas(mesh_.triangle_count());
    double total = 0.0;
    for (size_t f = 0; f < areas.size(); ++f) {
        const uint32_t* idx = &mesh_.indices[3 * f];
        const Point3f& p0 = mesh_.positions[idx[0]];
        areas[f] = 0.5f * norm(cross(mesh_.positions[idx[1]] - p0, mesh_.positions[idx[2]] - p0));
        total += areas[f];
    }
    if (!(total > 0.0)) props.fail_here("mesh \"{}\" has zero surface area", name_);
    area_distr_ = DiscreteDistribution(areas);
    area_ = float(total);
    inv_area_ = float(1.0 / total);

    init_common(props);
}

SurfaceInteraction MeshShape::compute_surface_interaction(const Ray& ray, float t, uint32_t prim_index,
                                                          Vec2f prim_uv) const {
    const uint32_t* idx = &mesh_.indices[3 * size_t(prim_index)];
    const Point3f &p0 = mesh_.positions[idx[0]], &p1 = mesh_.positions[idx[1]], &p2 = mesh_.positions[idx[2]];
    float b1 = prim_uv.x, b2 = prim_uv.y, b0 = 1.f - b1 - b2;

    SurfaceInteraction si;
    si.t = t;
    si.p = p0 * b0 + p1 * b1 + p2 * b2;
    Vec3f dp0 = p1 - p0, dp1 = p2 - p0;
    si.n = normalize(cross(dp0, dp1));
    si.uv = {b1, b2};
    coordinate_system(si.n, si.dp_du, si.dp_dv);

    if (!mesh_.uvs.empty()) {
        const Vec2f &uv0 = mesh_.uvs[idx[0]], &uv1 = mesh_.uvs[idx[1]], &uv2 = mesh_.uvs[idx[2]];
        si.uv = uv0 * b0 + uv1 * b1 + uv2 * b2;
        Vec2f duv0 = uv1 - uv0, duv1 = uv2 - uv0;
        float det = duv0.x * duv1.y - duv0.y * duv1.x;
        if (det != 0.f) {
            float inv_det = 1.f / det;
            si.dp_du = (dp0 * duv1.y - dp1 * duv0.y) * inv_det;
            si.dp_dv = (dp1 * duv0.x - dp0 * duv1.x) * inv_det;
        }
    }

    if (!mesh_.normals.empty()) {
        Normal3f ns = mesh_.normals[idx[0]] * b0 + mesh_.normals[idx[1]] * b1 + mesh_.normals[idx[2]] * b2;
        float len = norm(ns);
        si.sh_frame.n = len > 0.f ? ns / len : si.n;
    } else {
        si.sh_frame.n = si.n;
    }
    if (flip_normals_) {
        si.n = -si.n;
        si.sh_frame.n = -si.sh_frame.n;
    }
    si.shape = this;
    si.prim_index = prim_index;
    finalize_shading_frame(si, ray);
    return si;
}

PositionSample MeshShape::sample_position(Point2f u) const {
    size_t f = area_distr_.sample_reuse(u.y);
    const uint32_t* idx = &mesh_.indices[3 * f];
    const Point3f &p0 = mesh_.positions[idx[0]], &p1 = mesh_.positions[idx[1]], &p2 = mesh_.positions[idx[2]];
    Vec3f e0 = p1 - p0, e1 = p2 - p0;
    Point2f b = warp::square_to_uniform_triangle(u);
    float b0 = 1.f - b.x - b.y;

    PositionSample ps;
    ps.p = p0 + e0 * b.x + e1 * b.y;
    ps.pdf = inv_area_;
    ps.uv =
        mesh_.uvs.empty() ? b : mesh_.uvs[idx[0]] * b0 + mesh_.uvs[idx[1]] * b.x + mesh_.uvs[idx[2]] * b.y;
    Normal3f n = mesh_.normals.empty()
                     ? cross(e0, e1)
                     : mesh_.normals[idx[0]] * b0 + mesh_.normals[idx[1]] * b.x + mesh_.normals[idx[2]] * b.y;
    // Interpolated normals can cancel out (inconsistent file normals): fall back to the face normal.
    if (!(squared_norm(n) > 0.f)) n = cross(e0, e1);
    ps.n = normalize(n);
    if (flip_normals_) ps.n = -ps.n;
    return ps;
}

void MeshShape::check_attributes(const Properties& props) const {
    for (const MeshAttribute& a : mesh_.attributes) {
        const size_t count = a.per_face() ? mesh_.triangle_count() : mesh_.positions.size();
        if ((a.channels != 1 && a.channels != 3) || a.values.size() != count * size_t(a.channels))
            props.fail_here("mesh \"{}\": attribute '{}' has {} values for {} {} of {} channel(s)", name_, a.name,
                            a.values.size(), count, a.per_face() ? "triangles" : "vertices", a.channels);
    }
}

const MeshAttribute* MeshShape::find_attribute(const std::string& name) const {
    for (const MeshAttribute& a : mesh_.attributes)
        if (a.name == name) return &a;
    return nullptr;
}

int MeshShape::attribute_channels(const std::string& name) const {
    const MeshAttribute* a = find_attribute(name);
    return a ? a->channels : 0;
}

namespace {

// Barycentrics (b0, b1, b2) of `p` in triangle (p0, p1, p2), from the sub-triangle areas as
// Mitsuba's Mesh::barycentric_coordinates does (the hit point lies in the triangle's plane).
Vec3f mesh_barycentrics(const Point3f& p, const Point3f& p0, const Point3f& p1, const Point3f& p2) {
    const Vec3f e1 = p1 - p0, e2 = p2 - p0, rel = p - p0;
    const float d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
    const float r1 = dot(rel, e1), r2 = dot(rel, e2);
    const float det = d11 * d22 - d12 * d12;
    if (!(det > 0.f)) return Vec3f(1.f, 0.f, 0.f);  // degenerate triangle (zero area): never hit
    const float b1 = (d22 * r1 - d12 * r2) / det, b2 = (d11 * r2 - d12 * r1) / det;
    return Vec3f(1.f - b1 - b2, b1, b2);
}

Color3 attribute_value(const MeshAttribute& a, size_t index) {
    const float* v = &a.values[index * size_t(a.channels)];
    return a.channels == 1 ? Color3(v[0]) : Color3(v[0], v[1], v[2]);
}

}  // namespace

Color3 MeshShape::eval_attribute(const std::string& name, const SurfaceInteraction& si) const {
    const MeshAttribute* a = find_attribute(name);
    if (!a) return Color3(0.f);  // the scene loader refuses textures naming an absent attribute
    if (a->per_face()) return attribute_value(*a, si.prim_index);
    const uint32_t* idx = &mesh_.indices[3 * size_t(si.prim_index)];
    const Vec3f b = mesh_barycentrics(si.p, mesh_.positions[idx[0]], mesh_.positions[idx[1]], mesh_.positions[idx[2]]);
    return attribute_value(*a, idx[0]) * b.x + attribute_value(*a, idx[1]) * b.y + attribute_value(*a, idx[2]) * b.z;
}

std::string MeshShape::to_string() const {
    return fmt::format("Mesh[name=\"{}\", vertices={}, triangles={}, area={}]", name_, mesh_.positions.size(),
                       mesh_.triangle_count(), area_);
}

}  // namespace volguide
