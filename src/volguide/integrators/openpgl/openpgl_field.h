#pragma once
// The Open PGL guiding field of one render (openpgl_volpath): its device, its field (kd-tree of
// parallax-aware VMMs, Open PGL's defaults with deterministic training) over the scene's bounds,
// and the sample storage the training passes fill. add_samples may be called from any thread
// during a pass (Open PGL's storage is a concurrent vector); update() runs between passes.
#include <memory>

#include <openpgl/cpp/OpenPGL.h>

#include "volguide/core/bbox.h"

namespace volguide {

class OpenPglField {
  public:
    // threads: the render's worker count (the device limits Open PGL's own TBB work to it).
    OpenPglField(const BBox3f& bounds, int threads, int max_samples_per_leaf);
    OpenPglField(const OpenPglField&) = delete;
    OpenPglField& operator=(const OpenPglField&) = delete;

    const openpgl::cpp::Field& field() const { return *field_; }
    // Whether an update has run: before it, every sampling distribution's Init fails.
    bool trained() const { return updates_ > 0; }
    int updates() const { return updates_; }

    void add_samples(const openpgl::cpp::SampleData* samples, size_t n) { storage_.AddSamples(samples, n); }
    // The samples added since the last update (what the next update trains on).
    const openpgl::cpp::SampleStorage& pending_samples() const { return storage_; }
    // Field::Update with the samples added since the last update, then drops them (as Cycles does).
    void update();
    size_t samples_total() const { return samples_total_; }

  private:
    std::unique_ptr<openpgl::cpp::Device> device_;
    openpgl::cpp::FieldConfig config_;  // a config creates exactly one field
    std::unique_ptr<openpgl::cpp::Field> field_;
    openpgl::cpp::SampleStorage storage_;
    int updates_ = 0;
    size_t samples_total_ = 0;
};

// Open PGL's vector types from volguide's.
inline pgl_point3f pgl_point(const Point3f& p) { return openpgl::cpp::Point3(p.x, p.y, p.z); }
inline pgl_vec3f pgl_vec(const Vec3f& v) { return openpgl::cpp::Vector3(v.x, v.y, v.z); }
inline Vec3f from_pgl(const pgl_vec3f& v) { return Vec3f(v.x, v.y, v.z); }

}  // namespace volguide
