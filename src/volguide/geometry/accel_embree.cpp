// Accel on Embree 3: the only translation unit that includes Embree. Triangle meshes share
// their vertex/index buffers with Embree; analytic shapes are user geometries whose callbacks
// call Shape::intersect. A shapegroup is its own Embree scene, built once and placed by Embree
// instances (one per `instance`). Scenes are built in robust mode with high quality.
#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <map>
#include <mutex>
#include <stdexcept>
#include <string>

#include "volguide/core/tsan.h"
#include "volguide/geometry/accel.h"
#include "volguide/geometry/instance.h"

namespace volguide {

namespace {

struct ErrorState {
    std::mutex mutex;
    std::string message;
};

void error_callback(void* user, RTCError code, const char* str) {
    auto* state = static_cast<ErrorState*>(user);
    std::lock_guard<std::mutex> lock(state->mutex);
    if (state->message.empty())
        state->message = fmt::format("Embree error {}: {}", int(code), str ? str : "");
}

// Called by Embree's BVH build (rtcCommitScene) on TBB's threads: in a ThreadSanitizer build it
// acquires what the building thread released on the shape's address before the commit, and
// releases what the building thread acquires after it (core/parallel.h).
void user_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* shape = static_cast<const Shape*>(args->geometryUserPtr);
    tsan_acquire(shape);
    BBox3f b = shape->primitive_bbox(args->primID);
    args->bounds_o->lower_x = b.lo.x;
    args->bounds_o->lower_y = b.lo.y;
    args->bounds_o->lower_z = b.lo.z;
    args->bounds_o->upper_x = b.hi.x;
    args->bounds_o->upper_y = b.hi.y;
    args->bounds_o->upper_z = b.hi.z;
    tsan_release(shape);
}

// Only rtcIntersect1/rtcOccluded1 are used, so the packets have width 1 and the N-wide
// structures have the layout of RTCRayHit / RTCRay.
void user_intersect(const RTCIntersectFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* shape = static_cast<const Shape*>(args->geometryUserPtr);
    RTCRayHit* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    Ray ray({rh->ray.org_x, rh->ray.org_y, rh->ray.org_z}, {rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z},
            rh->ray.tfar);
    float t;
    Vec2f uv;
    if (!shape->intersect_primitive(ray, args->primID, t, uv) || !(t >= rh->ray.tnear)) return;
    rh->ray.tfar = t;
    rh->hit.u = uv.x;
    rh->hit.v = uv.y;
    rh->hit.Ng_x = rh->hit.Ng_y = 0.f;
    rh->hit.Ng_z = 1.f;
    rh->hit.primID = args->primID;
    rh->hit.geomID = args->geomID;
    rh->hit.instID[0] = args->context->instID[0];  // invalid outside an instance
}

void user_occluded(const RTCOccludedFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* shape = static_cast<const Shape*>(args->geometryUserPtr);
    RTCRay* r = reinterpret_cast<RTCRay*>(args->ray);
    Ray ray({r->org_x, r->org_y, r->org_z}, {r->dir_x, r->dir_y, r->dir_z}, r->tfar);
    float t;
    Vec2f uv;
    // -Infinity: Embree's "occluded" mark.
    if (shape->intersect_primitive(ray, args->primID, t, uv) && t >= r->tnear) r->tfar = -Infinity;
}

}  // namespace

struct Accel::Impl {
    ErrorState errors;
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<const Shape*> shapes;                    // by geometry id
    // A shapegroup's own scene, built once however many instances place it.
    struct GroupScene {
        RTCScene scene = nullptr;
        std::vector<const Shape*> shapes;  // by geometry id inside the group
    };
    std::map<const ShapeGroup*, GroupScene> groups;
    std::vector<std::vector<Point3f>> padded_positions;  // copies when a buffer cannot be shared
    std::vector<std::vector<uint32_t>> padded_indices;

    void check(const char* what) {
        RTCError code = rtcGetDeviceError(device);
        std::string msg;
        {
            std::lock_guard<std::mutex> lock(errors.mutex);
            msg = errors.message;
        }
        if (code != RTC_ERROR_NONE || !msg.empty())
            throw std::runtime_error(
                fmt::format("{}: {}", what, msg.empty() ? "Embree error " + std::to_string(int(code)) : msg));
    }

    // Embree reads 3-float/3-int elements with 16-byte loads, so the storage must extend at
    // least 4 bytes past the last element. Shapes reserve one spare element; otherwise the data
    // is copied with padding.
    template <typename T>
    const T* padded(const std::vector<T>& v, std::vector<std::vector<T>>& copies) {
        if (v.capacity() > v.size()) return v.data();
        auto& c = copies.emplace_back();
        c.reserve(v.size() + 1);
        c.assign(v.begin(), v.end());
        return c.data();
    }

    void add_triangles(RTCScene target, std::vector<const Shape*>& ids, const Shape* shape,
                       const TriangleMesh& mesh) {
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        const Point3f* pos = padded(mesh.positions, padded_positions);
        const uint32_t* idx = padded(mesh.indices, padded_indices);
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, pos, 0,
                                   sizeof(Point3f), mesh.positions.size());
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, idx, 0,
                                   3 * sizeof(uint32_t), mesh.triangle_count());
        attach(target, ids, geom, shape);
    }

    void add_user(RTCScene target, std::vector<const Shape*>& ids, const Shape* shape) {
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(geom, shape->primitive_count());
        rtcSetGeometryUserData(geom, const_cast<Shape*>(shape));
        rtcSetGeometryBoundsFunction(geom, user_bounds, nullptr);
        rtcSetGeometryIntersectFunction(geom, user_intersect);
        rtcSetGeometryOccludedFunction(geom, user_occluded);
        attach(target, ids, geom, shape);
    }

    void add_shape(RTCScene target, std::vector<const Shape*>& ids, const Shape* s) {
        if (const auto* instance = dynamic_cast<const Instance*>(s))
            add_instance(instance);
        else if (const TriangleMesh* mesh = s->triangle_mesh())
            add_triangles(target, ids, s, *mesh);
        else
            add_user(target, ids, s);
    }

    // The group's scene (built and committed on first use), placed by an Embree instance.
    void add_instance(const Instance* instance) {
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(geom, group_scene(instance->group()));
        const Matrix4& m = instance->to_world().matrix();
        float xfm[12];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) xfm[4 * r + c] = float(m.m[r][c]);
        rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
        attach(scene, shapes, geom, instance);
    }

    RTCScene group_scene(const ShapeGroup& group) {
        auto [it, inserted] = groups.try_emplace(&group);
        GroupScene& g = it->second;
        if (!inserted) return g.scene;
        g.scene = rtcNewScene(device);
        rtcSetSceneFlags(g.scene, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(g.scene, RTC_BUILD_QUALITY_HIGH);
        for (const auto& s : group.shapes()) add_shape(g.scene, g.shapes, s.get());
        for (const Shape* s : g.shapes) tsan_release(s);
        rtcCommitScene(g.scene);
        for (const Shape* s : g.shapes) tsan_acquire(s);
        check("building a shapegroup's acceleration structure");
        return g.scene;
    }

    void attach(RTCScene target, std::vector<const Shape*>& ids, RTCGeometry geom, const Shape* shape) {
        rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
        rtcCommitGeometry(geom);
        unsigned id = rtcAttachGeometry(target, geom);
        rtcReleaseGeometry(geom);
        check("adding a shape to the acceleration structure");
        if (id != ids.size()) throw std::logic_error("Embree returned an unexpected geometry id");
        ids.push_back(shape);
    }
};

Accel::Accel(const std::vector<const Shape*>& shapes) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    // The device's settings are strings the BVH build compares on whichever TBB thread runs it;
    // TSan cannot see Embree hand the build over, so it would report their creation here as racing
    // with that read (no volguide code runs inside rtcNewDevice).
    {
        [[maybe_unused]] TsanIgnoredAccesses embree_device_setup;
        m.device = rtcNewDevice(nullptr);
    }
    if (!m.device)
        throw std::runtime_error(
            fmt::format("cannot create the Embree device (error {})", int(rtcGetDeviceError(nullptr))));
    rtcSetDeviceErrorFunction(m.device, error_callback, &m.errors);
    m.scene = rtcNewScene(m.device);
    rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_HIGH);
    m.check("creating the Embree scene");
    m.padded_positions.reserve(shapes.size());
    m.padded_indices.reserve(shapes.size());
    for (const Shape* s : shapes) m.add_shape(m.scene, m.shapes, s);
    // The build is a fork/join of Embree's (on TBB's threads) that ThreadSanitizer cannot see:
    // the user geometries' bounds callbacks see everything before the commit, and everything
    // after it sees them (no-ops outside a ThreadSanitizer build).
    for (const Shape* s : m.shapes) tsan_release(s);
    rtcCommitScene(m.scene);
    for (const Shape* s : m.shapes) tsan_acquire(s);
    m.check("building the acceleration structure");
}

Accel::~Accel() {
    // Freeing what the build threads read (see the constructor).
    [[maybe_unused]] TsanIgnoredAccesses embree_teardown;
    if (impl_->scene) rtcReleaseScene(impl_->scene);
    for (auto& [group, g] : impl_->groups)
        if (g.scene) rtcReleaseScene(g.scene);
    if (impl_->device) rtcReleaseDevice(impl_->device);
}

bool Accel::intersect(const Ray& ray, SurfaceInteraction& si) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x;
    rh.ray.org_y = ray.o.y;
    rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x;
    rh.ray.dir_y = ray.d.y;
    rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = 0.f;
    rh.ray.tfar = ray.tmax;
    rh.ray.time = 0.f;
    rh.ray.mask = ~0u;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    const Vec2f prim_uv(rh.hit.u, rh.hit.v);
    if (rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
        const auto* instance = static_cast<const Instance*>(impl_->shapes[rh.hit.instID[0]]);
        const Shape& inner = *instance->group().shapes()[rh.hit.geomID];
        si = instance->interaction(inner, ray, rh.ray.tfar, rh.hit.primID, prim_uv);
        return true;
    }
    const Shape* shape = impl_->shapes[rh.hit.geomID];
    si = shape->compute_surface_interaction(ray, rh.ray.tfar, rh.hit.primID, prim_uv);
    return true;
}

bool Accel::occluded(const Ray& ray) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    r.org_x = ray.o.x;
    r.org_y = ray.o.y;
    r.org_z = ray.o.z;
    r.dir_x = ray.d.x;
    r.dir_y = ray.d.y;
    r.dir_z = ray.d.z;
    r.tnear = 0.f;
    r.tfar = ray.tmax;
    r.time = 0.f;
    r.mask = ~0u;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(impl_->scene, &ctx, &r);
    return r.tfar < 0.f;
}

}  // namespace volguide
