#include "volguide/geometry/shapes/sdfgrid.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "volguide/geometry/shapes/mesh_files.h"
#include "volguide/geometry/shapes/shape_plugins.h"
#include "volguide/geometry/surface_frame.h"
#include "volguide/media/grid_data.h"

namespace volguide {

namespace {

// c3 t³ + c2 t² + c1 t + c0: the trilinear interpolant along a ray in voxel coordinates.
struct SdfCubic {
    float c0 = 0.f, c1 = 0.f, c2 = 0.f, c3 = 0.f;
    float operator()(float t) const { return ((c3 * t + c2) * t + c1) * t + c0; }
};

// The cubic for corner values s[x + 2y + 4z] and the ray o + t d (voxel coordinates, o at t = 0):
// f = a0 + a1 x + a2 y + a3 z + a4 xy + a5 xz + a6 yz + a7 xyz expanded in t.
SdfCubic sdf_voxel_cubic(const std::array<float, 8>& s, const Vec3f& o, const Vec3f& d) {
    const float a0 = s[0], a1 = s[1] - s[0], a2 = s[2] - s[0], a3 = s[4] - s[0];
    const float a4 = s[3] - s[1] - s[2] + s[0], a5 = s[5] - s[1] - s[4] + s[0],
                a6 = s[6] - s[2] - s[4] + s[0];
    const float a7 = s[7] - s[3] - s[5] - s[6] + s[1] + s[2] + s[4] - s[0];
    SdfCubic c;
    c.c0 = a0 + a1 * o.x + a2 * o.y + a3 * o.z + a4 * o.x * o.y + a5 * o.x * o.z + a6 * o.y * o.z +
           a7 * o.x * o.y * o.z;
    c.c1 = a1 * d.x + a2 * d.y + a3 * d.z + a4 * (o.x * d.y + o.y * d.x) + a5 * (o.x * d.z + o.z * d.x) +
           a6 * (o.y * d.z + o.z * d.y) + a7 * (d.x * o.y * o.z + o.x * d.y * o.z + o.x * o.y * d.z);
    c.c2 = a4 * d.x * d.y + a5 * d.x * d.z + a6 * d.y * d.z +
           a7 * (d.x * d.y * o.z + d.x * o.y * d.z + o.x * d.y * d.z);
    c.c3 = a7 * d.x * d.y * d.z;
    return c;
}

// Real roots r0 <= r1 of a t² + b t + c (a linear equation when a = 0); false when there are none.
bool sdf_quadratic_roots(float a, float b, float c, float& r0, float& r1) {
    if (a == 0.f) {
        if (b == 0.f) return false;
        r0 = r1 = -c / b;
        return true;
    }
    const float disc = b * b - 4.f * a * c;
    if (disc < 0.f) return false;
    const float q = -0.5f * (b + std::copysign(std::sqrt(disc), b));
    r0 = q / a;
    r1 = q != 0.f ? c / q : r0;
    if (r0 > r1) std::swap(r0, r1);
    return true;
}

// False position on [t0, t1] with f(t0) f(t1) <= 0, to |t1 - t0| < 1e-5 or 50 steps (Mitsuba's bounds).
float sdf_false_position(const SdfCubic& f, float t0, float t1, float f0, float f1) {
    float t = t0;
    for (int i = 0; i <= 50; ++i) {
        t = t0 + (t1 - t0) * (-f0 / (f1 - f0));
        const float ft = f(t);
        if (ft * f0 <= 0.f) {
            t1 = t;
            f1 = ft;
        } else {
            t0 = t;
            f0 = ft;
        }
        if (std::abs(t0 - t1) < 1e-5f) break;
    }
    return t;
}

// The first root of f in [0, t_end]: the derivative's roots split the interval into monotonic pieces;
// the first piece with a sign change brackets it.
bool sdf_first_root(const SdfCubic& f, float t_end, float& t) {
    float t_near = 0.f, t_far = t_end, r0 = 0.f, r1 = 0.f;
    if (sdf_quadratic_roots(3.f * f.c3, 2.f * f.c2, f.c1, r0, r1)) {
        for (float r : {r0, r1})
            if (t_near <= r && r <= t_far) (f(t_near) * f(r) <= 0.f ? t_far : t_near) = r;
    }
    const float f_near = f(t_near), f_far = f(t_far);
    if (!(f_near * f_far <= 0.f)) return false;
    t = f_near == f_far ? t_near : sdf_false_position(f, t_near, t_far, f_near, f_far);
    return std::isfinite(t);
}

// The ray's parameter interval inside the box (t0 <= t1), from t = 0 on.
bool sdf_box_interval(const BBox3f& b, const Ray& ray, float& t0, float& t1) {
    t0 = 0.f;
    t1 = Infinity;
    for (int a = 0; a < 3; ++a) {
        const float inv = 1.f / ray.d[a];
        float n = (b.lo[a] - ray.o[a]) * inv, f = (b.hi[a] - ray.o[a]) * inv;
        if (n > f) std::swap(n, f);
        if (std::isnan(n) || std::isnan(f)) {
            if (ray.o[a] < b.lo[a] || ray.o[a] > b.hi[a]) return false;
            continue;
        }
        t0 = std::max(t0, n);
        t1 = std::min(t1, f);
    }
    return t0 < t1;
}

SdfValues sdf_values_from_file(const Properties& props) {
    const std::string path = resolve_filename(props);
    const GridData g = read_vol_file(path);
    if (g.channels != 1)
        props.fail_at("filename", "sdfgrid: '{}' has {} channels, expected 1", path, g.channels);
    if (g.nx < 2 || g.ny < 2 || g.nz < 2)
        props.fail_at("filename", "sdfgrid: '{}' is {}x{}x{}: at least 2 values per axis are needed", path,
                      g.nx, g.ny, g.nz);
    return SdfValues{g.nx, g.ny, g.nz, g.values};
}

bool sdf_normals_smooth(const Properties& props) {
    const std::string mode = props.get_string("normals", "smooth");
    if (mode != "smooth" && mode != "analytic")
        props.fail_at("normals", "sdfgrid: normals must be 'smooth' or 'analytic', got '{}'", mode);
    return mode == "smooth";
}

}  // namespace

SdfGrid::SdfGrid(SdfValues grid, const Transform& to_world, bool smooth_normals) : grid_(std::move(grid)) {
    build(to_world, smooth_normals);
}

SdfGrid::SdfGrid(const Properties& props) : grid_(sdf_values_from_file(props)) {
    const bool smooth = sdf_normals_smooth(props);
    try {
        build(props.get_transform("to_world"), smooth);
    } catch (const std::invalid_argument& e) {
        props.fail_at("filename", "sdfgrid: {}", e.what());
    }
    init_common(props);
    if (emitter_)
        props.fail_at(props.children("emitter")[0]->name, "sdfgrid: an SDF grid cannot be an area emitter");
}

void SdfGrid::build(const Transform& to_world, bool smooth_normals) {
    const SdfValues& g = grid_;
    if (g.nx < 2 || g.ny < 2 || g.nz < 2)
        throw std::invalid_argument("at least 2 values per axis are needed");
    if (g.values.size() != size_t(g.nx) * g.ny * g.nz)
        throw std::invalid_argument("value count does not match");
    to_world_ = to_world;
    to_object_ = to_world.inverse();
    smooth_ = smooth_normals;
    voxel_size_ = Vec3f(1.f / float(g.nx - 1), 1.f / float(g.ny - 1), 1.f / float(g.nz - 1));
    for (int z = 0; z + 1 < g.nz; ++z)
        for (int y = 0; y + 1 < g.ny; ++y)
            for (int x = 0; x + 1 < g.nx; ++x) {
                BBox3f local;
                if (!tight_box(x, y, z, local)) continue;
                BBox3f world;
                for (int c = 0; c < 8; ++c) {
                    const Point3f q((c & 1 ? local.hi.x : local.lo.x) + float(x),
                                    (c & 2 ? local.hi.y : local.lo.y) + float(y),
                                    (c & 4 ? local.hi.z : local.lo.z) + float(z));
                    const Point3f p = to_world_.apply_point(q * voxel_size_);
                    if (c == 0) world = BBox3f{p, p};
                    world.expand(p);
                }
                voxels_.push_back(uint32_t(x + (g.nx - 1) * (y + (g.ny - 1) * z)));
                boxes_.push_back(world);
            }
    if (voxels_.empty())
        throw std::invalid_argument("the surface crosses no voxel (no sign change in the grid)");
}

float SdfGrid::corner(int x, int y, int z) const {
    x = std::clamp(x, 0, grid_.nx - 1);
    y = std::clamp(y, 0, grid_.ny - 1);
    z = std::clamp(z, 0, grid_.nz - 1);
    return grid_.values[(size_t(z) * grid_.ny + y) * grid_.nx + x];
}

// Hansson-Söderlund and Akenine-Möller's tight box: the corners where the SDF is 0 and the points where
// it changes sign along the twelve edges (voxel-local coordinates).
bool SdfGrid::tight_box(int x, int y, int z, BBox3f& box) const {
    std::array<float, 8> f;
    bool all_pos = true, all_neg = true;
    for (int c = 0; c < 8; ++c) {
        f[c] = corner(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1));
        all_pos = all_pos && f[c] > 0.f;
        all_neg = all_neg && f[c] < 0.f;
    }
    if (all_pos || all_neg) return false;
    box = BBox3f{Point3f(1.f), Point3f(0.f)};  // empty until a point is added
    auto corner_pos = [](int c) { return Point3f(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1)); };
    for (int c = 0; c < 8; ++c)
        if (f[c] == 0.f) box.expand(corner_pos(c));
    for (int c1 = 0; c1 < 8; ++c1)
        for (int axis = 0; axis < 3; ++axis) {
            if (c1 & (1 << axis)) continue;
            const int c2 = c1 | (1 << axis);
            if (!(f[c1] * f[c2] <= 0.f) || f[c1] == f[c2]) continue;
            box.expand(corner_pos(c1) + (corner_pos(c2) - corner_pos(c1)) * (f[c1] / (f[c1] - f[c2])));
        }
    return true;
}

float SdfGrid::value(const Point3f& p) const {
    // Grid index coordinates: corner i sits at p = i / (n - 1); clamped at the grid's faces.
    const Vec3f q(std::clamp(p.x * float(grid_.nx - 1), 0.f, float(grid_.nx - 1)),
                  std::clamp(p.y * float(grid_.ny - 1), 0.f, float(grid_.ny - 1)),
                  std::clamp(p.z * float(grid_.nz - 1), 0.f, float(grid_.nz - 1)));
    const int x = std::min(int(q.x), grid_.nx - 2), y = std::min(int(q.y), grid_.ny - 2),
              z = std::min(int(q.z), grid_.nz - 2);
    const float u = q.x - float(x), v = q.y - float(y), w = q.z - float(z);
    auto lerp = [](float a, float b, float s) { return a + (b - a) * s; };
    const float c00 = lerp(corner(x, y, z), corner(x + 1, y, z), u),
                c10 = lerp(corner(x, y + 1, z), corner(x + 1, y + 1, z), u);
    const float c01 = lerp(corner(x, y, z + 1), corner(x + 1, y, z + 1), u),
                c11 = lerp(corner(x, y + 1, z + 1), corner(x + 1, y + 1, z + 1), u);
    return lerp(lerp(c00, c10, v), lerp(c01, c11, v), w);
}

Vec3f SdfGrid::voxel_gradient(const Point3f& p, int vx, int vy, int vz) const {
    const Point3f lo(float(vx) * voxel_size_.x, float(vy) * voxel_size_.y, float(vz) * voxel_size_.z);
    return Vec3f(
        (value(Point3f(lo.x + voxel_size_.x, p.y, p.z)) - value(Point3f(lo.x, p.y, p.z))) / voxel_size_.x,
        (value(Point3f(p.x, lo.y + voxel_size_.y, p.z)) - value(Point3f(p.x, lo.y, p.z))) / voxel_size_.y,
        (value(Point3f(p.x, p.y, lo.z + voxel_size_.z)) - value(Point3f(p.x, p.y, lo.z))) / voxel_size_.z);
}

// The normalised gradients of the 2x2x2 voxels around the corner nearest p, blended trilinearly by p's
// position between those voxels' centres; voxels below index 0 are left out, and an axis whose whole
// lower or upper side is left out takes its weight from the other side (the JCGT paper's smooth normal
// as Mitsuba evaluates it).
Vec3f SdfGrid::smooth_normal(const Point3f& p) const {
    const Vec3f s(p.x * float(grid_.nx - 1), p.y * float(grid_.ny - 1), p.z * float(grid_.nz - 1));
    const int bx = int(std::round(s.x)) - 1, by = int(std::round(s.y)) - 1, bz = int(std::round(s.z)) - 1;
    std::array<Vec3f, 8> n;
    std::array<bool, 8> ok;
    for (int c = 0; c < 8; ++c) {
        const int x = bx + (c & 1), y = by + ((c >> 1) & 1), z = bz + ((c >> 2) & 1);
        ok[c] = x >= 0 && y >= 0 && z >= 0;
        n[c] = ok[c] ? normalize(voxel_gradient(p, x, y, z)) : Vec3f(0.f);
    }
    Vec3f f(s.x - float(bx + 1) + 0.5f, s.y - float(by + 1) + 0.5f, s.z - float(bz + 1) + 0.5f);
    for (int axis = 0; axis < 3; ++axis) {
        bool any_lo = false, any_hi = false;
        for (int c = 0; c < 8; ++c) {
            bool& side = (c & (1 << axis)) ? any_hi : any_lo;
            side = side || ok[c];
        }
        if (!any_lo) f[axis] = 1.f;
        if (!any_hi) f[axis] = 0.f;
    }
    Vec3f out(0.f);
    for (int c = 0; c < 8; ++c)
        out += n[c] * ((c & 1 ? f.x : 1.f - f.x) * (c & 2 ? f.y : 1.f - f.y) * (c & 4 ? f.z : 1.f - f.z));
    return out;
}

bool SdfGrid::intersect_primitive(const Ray& world_ray, uint32_t prim, float& t, Vec2f& prim_uv) const {
    const uint32_t index = voxels_[prim];
    const int rx = grid_.nx - 1, ry = grid_.ny - 1;
    const int x = int(index % uint32_t(rx)), y = int((index / uint32_t(rx)) % uint32_t(ry)),
              z = int(index / uint32_t(rx * ry));
    // Object space keeps the ray's parameter (the direction is transformed, not normalised).
    const Ray ray(to_object_.apply_point(world_ray.o), to_object_.apply_vector(world_ray.d), world_ray.tmax);
    const Point3f lo(float(x) * voxel_size_.x, float(y) * voxel_size_.y, float(z) * voxel_size_.z);
    float t0, t1;
    if (!sdf_box_interval(BBox3f{lo, lo + voxel_size_}, ray, t0, t1)) return false;
    // Voxel coordinates: the voxel is [0,1]^3.
    const Vec3f scale(float(rx), float(ry), float(grid_.nz - 1));
    const Point3f entry = ray.o + ray.d * t0;
    const Vec3f o =
        Vec3f(entry.x * scale.x - float(x), entry.y * scale.y - float(y), entry.z * scale.z - float(z));
    const Vec3f d(ray.d.x * scale.x, ray.d.y * scale.y, ray.d.z * scale.z);
    std::array<float, 8> s;
    for (int c = 0; c < 8; ++c) s[c] = corner(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1));
    float root;
    if (!sdf_first_root(sdf_voxel_cubic(s, o, d), t1 - t0, root)) return false;
    t = t0 + root;
    prim_uv = Vec2f(0.f, 0.f);
    return t >= 0.f && t <= world_ray.tmax;
}

SurfaceInteraction SdfGrid::compute_surface_interaction(const Ray& ray, float t, uint32_t prim_index,
                                                        Vec2f) const {
    SurfaceInteraction si;
    si.t = t;
    const Point3f local = to_object_.apply_point(ray.o + ray.d * t);
    const Vec3f s(local.x * float(grid_.nx - 1), local.y * float(grid_.ny - 1),
                  local.z * float(grid_.nz - 1));
    const Vec3f grad = voxel_gradient(local, int(s.x), int(s.y), int(s.z));
    si.p = to_world_.apply_point(local);
    si.n = normalize(to_world_.apply_normal(grad));
    si.sh_frame.n = smooth_ ? normalize(to_world_.apply_normal(smooth_normal(local))) : si.n;
    si.uv = Vec2f(0.f, 0.f);
    si.dp_du = si.dp_dv = Vec3f(0.f);
    si.shape = this;
    si.prim_index = prim_index;
    finalize_shading_frame(si, ray);
    return si;
}

BBox3f SdfGrid::bbox() const {
    BBox3f b;
    for (int c = 0; c < 8; ++c) {
        const Point3f p =
            to_world_.apply_point(Point3f(float(c & 1), float((c >> 1) & 1), float((c >> 2) & 1)));
        if (c == 0) b = BBox3f{p, p};
        b.expand(p);
    }
    return b;
}

std::string SdfGrid::to_string() const {
    return fmt::format("sdfgrid[{}x{}x{}, {} voxels crossed, normals={}]", grid_.nx, grid_.ny, grid_.nz,
                       voxels_.size(), smooth_ ? "smooth" : "analytic");
}

ObjectPtr create_sdfgrid_shape(const Properties& props) {
    return std::make_shared<SdfGrid>(props);
}

}  // namespace volguide
