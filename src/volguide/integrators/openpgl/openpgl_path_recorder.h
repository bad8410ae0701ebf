#pragma once
// Turns one camera path of volpath's walk into Open PGL path segments (PathSegmentStorage) and,
// through Open PGL's own PrepareSamples (its back-propagation, clamping, delta-chain distances),
// into training samples for the field.
//
// The walk (volpath_walk.h, with the recorder as its PathRecorder, path_recorder.h) reports, in
// path order, its scattering vertices (after their direction was sampled,
// with the path throughput T_k that includes everything up to and including that direction's
// weight f / p), its surface hits and every contribution c added to the estimate (already
// MIS-weighted). A contribution recorded after vertex k (and before vertex k + 1) is radiance
// arriving at x_k from its sampled direction: the emitter hit that direction found, or NEE at the
// next vertex. In Open PGL's terms it is a scattered contribution of segment k + 1 worth c / T_k,
// and segment k + 1's scattering weight is T_{k+1} / T_k (transmittance, RR and the direction
// weight in one factor; transmittance weights stay 1). PrepareSamples then gives vertex i the
// incident radiance sum over later contributions of (T_j / T_i)(c / T_j) = c / T_i, as Cycles'
// segments do. Contributions after the last vertex go to a closing segment at the surface hit
// that ended the path (or far along the direction when it left the scene).
//
// Direct light therefore enters training MIS-weighted (Open PGL's useNEEMiWeights mode): what
// the guided direction should sample beyond NEE. One recorder per thread, reused per path: the
// caller begins the path before the walk and ends it (into the field) after.
#include <vector>

#include <openpgl/cpp/OpenPGL.h>

#include "volguide/core/color.h"
#include "volguide/geometry/interaction.h"
#include "volguide/integrators/openpgl/openpgl_field.h"
#include "volguide/integrators/volpath/path_recorder.h"

namespace volguide {

class OpenPglPathRecorder final : public PathRecorder {
  public:
    // Segments kept per path at most (a longer path's later vertices are not recorded: less
    // training data, no bias; PrepareSamples is quadratic in the segment count).
    static constexpr int kMaxSegments = 1024;

    OpenPglPathRecorder();

    void begin_path();
    void add_contribution(const Color3& c) { pending_ += c; }
    // The path reached p (a surface hit or a medium vertex), or left the scene: where a closing
    // segment goes.
    void reached(const Point3f& p);
    void escaped();
    // A scattering vertex at x: wo its sampled direction (towards the light), wi towards the
    // previous vertex, pdf of wo, T the throughput after wo's weight.
    struct Vertex {
        Point3f x;
        Vec3f wo, wi;
        Vec3f n{0.f, 0.f, 1.f};
        float pdf = 1.f;
        Color3 throughput{1.f};
        bool volume = false;
        bool delta = false;
        float eta = 1.f;
        Color3 arriving_before{0.f};  // contributions recorded before this vertex, after the previous
    };
    void add_vertex(Vertex v);
    // Writes the path's segments, prepares Open PGL's samples and adds them to the field's storage.
    void end_path(OpenPglField& field);

    // The walk's reports (path_recorder.h) in the terms above.
    void record_contribution(const Color3& value) override { add_contribution(value); }
    void record_medium_hit(const MediumInteraction& mi) override;
    void record_medium_vertex(const Point3f& x, const Vec3f& w, float pdf, const Color3& throughput) override;
    void record_surface_hit(const SurfaceInteraction& si) override;
    void record_surface_vertex(const SurfaceInteraction& si, const BSDFSample& bs, const Vec3f& wo,
                               const Color3& throughput) override;

  private:
    openpgl::cpp::PathSegmentStorage segments_;
    std::vector<Vertex> path_;
    Color3 pending_{0.f};
    bool reached_after_last_vertex_ = false;
    bool escaped_ = false;
    Point3f reached_p_;
    Vec3f medium_wi_;  // the current medium vertex's direction towards the previous one
};

}  // namespace volguide
