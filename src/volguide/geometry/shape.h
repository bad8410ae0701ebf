#pragma once
// Shapes: triangle meshes (obj, ply, rectangle, cube) and analytic shapes (sphere, disk).
// Only geometry/accel_embree.cpp talks to Embree; shapes expose triangles or an exact
// intersection routine, and build the SurfaceInteraction of a hit.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "volguide/core/bbox.h"
#include "volguide/core/object.h"
#include "volguide/core/properties.h"
#include "volguide/geometry/interaction.h"

namespace volguide {

class BSDF;
class Emitter;
class Medium;

struct PositionSample {
    Point3f p;
    Normal3f n;
    Vec2f uv;
    float pdf = 0.f;  // w.r.t. area
};

// Sample of a point on a shape or emitter seen from a reference point.
struct DirectionSample {
    Point3f p;
    Normal3f n;          // zero for point lights and directions at infinity
    Vec2f uv;
    Vec3f d;             // unit direction from the reference point towards p
    float dist = 0.f;    // Infinity for emitters at infinity
    float pdf = 0.f;     // w.r.t. solid angle at the reference point (1 for delta emitters)
    bool delta = false;
    const Emitter* emitter = nullptr;
};

// A named per-vertex or per-face value of a mesh (Mitsuba 3's mesh attributes, read from PLY files):
// "vertex_<name>" is interpolated with the hit's barycentrics, "face_<name>" is constant per triangle.
struct MeshAttribute {
    std::string name;           // with its "vertex_" or "face_" prefix
    int channels = 1;           // 1 or 3
    std::vector<float> values;  // channels per vertex or per triangle
    bool per_face() const { return name.rfind("face_", 0) == 0; }
};

// World-space triangle data (to_world already applied).
struct TriangleMesh {
    std::vector<Point3f> positions;
    std::vector<Normal3f> normals;  // per vertex, empty = flat shading
    std::vector<Vec2f> uvs;         // per vertex, empty = barycentric defaults
    std::vector<uint32_t> indices;  // 3 per triangle
    std::vector<MeshAttribute> attributes;
    size_t triangle_count() const { return indices.size() / 3; }
};

class Shape : public Object {
public:
    virtual BBox3f bbox() const = 0;
    virtual float surface_area() const = 0;

    // Triangle shapes return their mesh; analytic shapes return nullptr and implement intersect().
    virtual const TriangleMesh* triangle_mesh() const { return nullptr; }
    // Analytic shapes: nearest hit with t in (0, ray.tmax); prim_uv is passed back to
    // compute_surface_interaction.
    virtual bool intersect(const Ray& ray, float& t, Vec2f& prim_uv) const { return false; }
    // Analytic shapes made of several primitives, each its own Embree user primitive (sdfgrid: one
    // per voxel the surface crosses); the defaults are one primitive, the whole shape.
    virtual uint32_t primitive_count() const { return 1; }
    virtual BBox3f primitive_bbox(uint32_t prim) const { return bbox(); }
    virtual bool intersect_primitive(const Ray& ray, uint32_t prim, float& t, Vec2f& prim_uv) const {
        return intersect(ray, t, prim_uv);
    }
    // Builds the full hit record; prim_uv are Embree's barycentrics for triangles.
    virtual SurfaceInteraction compute_surface_interaction(const Ray& ray, float t, uint32_t prim_index,
                                                           Vec2f prim_uv) const = 0;

    // Uniform (area-measure) position sampling.
    virtual PositionSample sample_position(Point2f u) const = 0;
    virtual float pdf_position(const PositionSample& ps) const { return 1.f / surface_area(); }
    // Solid-angle sampling from a reference point; the default converts sample_position.
    virtual DirectionSample sample_direction(const Interaction& ref, Point2f u) const;
    virtual float pdf_direction(const Interaction& ref, const DirectionSample& ds) const;

    // Mesh attributes (the `mesh_attribute` texture): the channel count of attribute `name`, 0 when the
    // shape has none of that name; and its value at a hit of this shape (1 channel: gray).
    virtual int attribute_channels(const std::string& name) const { return 0; }
    virtual Color3 eval_attribute(const std::string& name, const SurfaceInteraction& si) const {
        return Color3(0.f);
    }

    const BSDF* bsdf() const { return bsdf_.get(); }
    const Emitter* emitter() const { return emitter_.get(); }
    const std::shared_ptr<Emitter>& emitter_ptr() const { return emitter_; }
    bool is_emitter() const { return emitter_ != nullptr; }
    // Media on either side (nullptr = vacuum): interior is on the side opposite the normal.
    const Medium* interior_medium() const { return interior_.get(); }
    const Medium* exterior_medium() const { return exterior_.get(); }
    // The medium a ray leaving the surface in direction d (world) enters, given the geometric normal.
    const Medium* target_medium(const Normal3f& n, const Vec3f& d) const {
        return dot(n, d) > 0.f ? exterior_.get() : interior_.get();
    }
    // The scene gives shapes without a BSDF Mitsuba's default (diffuse, reflectance 0.5).
    void set_bsdf(std::shared_ptr<BSDF> bsdf) { bsdf_ = std::move(bsdf); }

protected:
    // Reads the optional BSDF child, area emitter child and `interior`/`exterior` media, and
    // attaches the emitter to this shape. Call from subclass constructors once the geometry exists.
    void init_common(const Properties& props);

    std::shared_ptr<BSDF> bsdf_;
    std::shared_ptr<Emitter> emitter_;
    std::shared_ptr<Medium> interior_, exterior_;
};

}  // namespace volguide
