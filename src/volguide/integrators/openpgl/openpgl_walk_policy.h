#pragma once
// openpgl_volpath's policy for volpath's walk (walk_policy.h): Open PGL's directional guiding as
// Blender Cycles uses it. The camera path's recording for Open PGL's training is the thread's
// OpenPglPathRecorder's (openpgl_path_recorder.h), a PathRecorder beside the policy.
//  - medium vertex: the field's VolumeSamplingDistribution at x (stochastic region lookup), times
//    a single HG lobe of the medium's mean cosine g about the ray's direction, in a one-sample
//    mixture p = phase_prob * p_phase + (1 - phase_prob) * p_guide; weight f_p / p. Not guided
//    for |g| >= 0.99 (Cycles), or where Open PGL has no region yet (Init fails): then p = p_phase.
//  - surface vertex with a diffuse reflection BSDF: SurfaceSamplingDistribution times the cosine
//    lobe about the shading normal on the incoming side, mixed with the BSDF (bsdf_prob).
//  - NEE's MIS and emitter hits' MIS use the same mixture pdf (direction_pdf / the walk's
//    last_pdf), so the estimator stays unbiased whatever the field.
// Distances are free flight, except with vsp=true (Open PGL 0.8): a segment leaving a guided vertex
// (medium, or diffuse surface) gets one scatter decision from that vertex's guiding distribution's
// VSP in the sampled direction (openpgl_vsp_distance.h); camera segments and segments after an
// unguided vertex stay free flight (Open PGL's per-pixel VSP buffer needs OIDN: not built here).
// There is no guided RR. One object per camera sample, over its thread's OpenPglThreadState.
#include <limits>

#include <openpgl/cpp/OpenPGL.h>

#include "volguide/integrators/volpath/walk_policy.h"
#include "volguide/integrators/openpgl/openpgl_field.h"
#include "volguide/integrators/openpgl/openpgl_path_recorder.h"
#include "volguide/integrators/openpgl/openpgl_settings.h"

namespace volguide {

// What one worker thread reuses across camera samples: Open PGL's sampling distributions
// (re-initialised at every vertex that uses them) and the path recorder (begun per path).
struct OpenPglThreadState {
    explicit OpenPglThreadState(const openpgl::cpp::Field* field) : volume(field), surface(field) {}
    openpgl::cpp::VolumeSamplingDistribution volume;
    openpgl::cpp::SurfaceSamplingDistribution surface;
    OpenPglPathRecorder recorder;
    // Direction decisions at medium / surface vertices, and how many of them were guided.
    int64_t medium_vertices = 0, guided_medium = 0, surface_vertices = 0, guided_surface = 0;
    // vsp=true: distance decisions, those made with Open PGL's VSP, and those of them that scattered.
    int64_t distance_decisions = 0, vsp_decisions = 0, vsp_scattered = 0;
};

class OpenPglWalkPolicy final : public WalkPolicy {
  public:
    // field: guides when trained().
    OpenPglWalkPolicy(const OpenPglSettings& settings, OpenPglThreadState& ts, OpenPglField& field);

    bool guides_distance() const override { return settings_.vsp; }
    FreeFlightSample sample_distance(const DistanceQuery& query, Sampler& sampler, DecisionRecord* record) override;

    void prepare_direction(const MediumInteraction& mi, Sampler& sampler) override;
    float direction_pdf(const MediumInteraction& mi, const Vec3f& wo) const override;
    PhaseSample sample_direction(const MediumInteraction& mi, Sampler& sampler, DecisionRecord* record) override;

    void prepare_surface_direction(const SurfaceInteraction& si, const BSDF& bsdf, const Medium* medium,
                                   Sampler& sampler) override;
    float surface_direction_pdf(const SurfaceQuery& at, const Vec3f& wo_local) const override;
    std::pair<BSDFSample, Color3> sample_surface_direction(const SurfaceQuery& at, float u1, Point2f u2,
                                                           Sampler& sampler, DecisionRecord* record) override;

  private:
    const OpenPglSettings& settings_;
    OpenPglThreadState& ts_;
    OpenPglField& field_;
    bool volume_ready_ = false;   // ts_.volume holds the current medium vertex's product
    bool surface_ready_ = false;  // ts_.surface holds the current surface vertex's product
    // vsp=true: Open PGL's VSP of the segment the last scattering vertex's sampled direction starts,
    // NaN when there is none (camera ray, unguided vertex, or already used by its one decision).
    float segment_vsp_ = std::numeric_limits<float>::quiet_NaN();
};

}  // namespace volguide
