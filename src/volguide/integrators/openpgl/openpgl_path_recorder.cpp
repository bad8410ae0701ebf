#include "volguide/integrators/openpgl/openpgl_path_recorder.h"

namespace volguide {

namespace {

// a / b per channel; 0 where b is 0 (then a is 0 too: nothing reaches past a zero throughput).
pgl_vec3f ratio(const Color3& a, const Color3& b) {
    const auto r = [](float x, float y) { return y > 0.f ? x / y : 0.f; };
    return openpgl::cpp::Vector3(r(a.r, b.r), r(a.g, b.g), r(a.b, b.b));
}

// Distance of the closing segment of a path that left the scene: Open PGL clamps source
// distances to twice its max distance (1e6), i.e. treats this as light from infinity.
constexpr float kEscapedDistance = 1e6f;

}  // namespace

OpenPglPathRecorder::OpenPglPathRecorder() {
    segments_.Reserve(kMaxSegments + 1);
    path_.reserve(64);
}

void OpenPglPathRecorder::begin_path() {
    path_.clear();
    pending_ = Color3(0.f);
    reached_after_last_vertex_ = false;
}

void OpenPglPathRecorder::reached(const Point3f& p) {
    reached_after_last_vertex_ = true;
    escaped_ = false;
    reached_p_ = p;
}

void OpenPglPathRecorder::escaped() {
    reached_after_last_vertex_ = true;
    escaped_ = true;
}

void OpenPglPathRecorder::add_vertex(Vertex v) {
    v.arriving_before = pending_;
    pending_ = Color3(0.f);
    reached_after_last_vertex_ = false;
    if (int(path_.size()) < kMaxSegments) path_.push_back(v);
}

void OpenPglPathRecorder::end_path(OpenPglField& field) {
    using namespace openpgl::cpp;
    if (path_.empty()) return;
    segments_.Clear();
    Color3 t_prev(1.f);
    for (const Vertex& v : path_) {
        PathSegment* s = segments_.NextSegment();
        SetPosition(s, pgl_point(v.x));
        SetDirectionIn(s, pgl_vec(v.wo));
        SetDirectionOut(s, pgl_vec(v.wi));
        SetNormal(s, pgl_vec(v.n));
        SetVolumeScatter(s, v.volume);
        SetPDFDirectionIn(s, v.pdf);
        SetIsDelta(s, v.delta);
        // Roughness only gates Open PGL's samples (> 0.01) and its delta-chain distances (< 0.3):
        // medium and non-delta surface vertices are fully rough (never the phase's g: README).
        SetRoughness(s, v.delta ? 0.f : 1.f);
        SetEta(s, v.eta);
        SetScatteringWeight(s, ratio(v.throughput, t_prev));
        SetScatteredContribution(s, ratio(v.arriving_before, t_prev));
        t_prev = v.throughput;
    }
    // Contributions after the last vertex: a closing segment where its direction ended.
    if (pending_.max_value() > 0.f) {
        const Vertex& last = path_.back();
        PathSegment* s = segments_.NextSegment();
        const Point3f end = reached_after_last_vertex_ && !escaped_ ? reached_p_ : last.x + last.wo * kEscapedDistance;
        SetPosition(s, pgl_point(end));
        SetDirectionOut(s, pgl_vec(-last.wo));
        SetScatteredContribution(s, ratio(pending_, t_prev));
    }
    // useNEEMiWeights, guideDirectLight: the contributions above carry their MIS weights already.
    segments_.PrepareSamples(true, true, true);
    size_t n = 0;
    const SampleData* samples = segments_.GetSamples(n);
    if (n > 0) field.add_samples(samples, n);
}

void OpenPglPathRecorder::record_medium_hit(const MediumInteraction& mi) {
    reached(mi.p);
    medium_wi_ = mi.wi;
}

void OpenPglPathRecorder::record_medium_vertex(const Point3f& x, const Vec3f& w, float pdf, const Color3& throughput) {
    Vertex v;
    v.x = x;
    v.wo = w;
    v.wi = medium_wi_;
    v.pdf = pdf;
    v.throughput = throughput;
    v.volume = true;
    add_vertex(v);
}

void OpenPglPathRecorder::record_surface_hit(const SurfaceInteraction& si) {
    if (si.is_valid())
        reached(si.p);
    else
        escaped();
}

void OpenPglPathRecorder::record_surface_vertex(const SurfaceInteraction& si, const BSDFSample& bs, const Vec3f& wo,
                                                const Color3& throughput) {
    // Null crossings (medium boundaries) are not scattering: the path goes on along the same line.
    if (bs.sampled_flags & bsdf_flags::Null) return;
    Vertex v;
    v.x = si.p;
    v.wo = wo;
    v.wi = si.to_world(si.wi);
    v.n = si.sh_frame.n;
    v.pdf = bs.pdf;
    v.throughput = throughput;
    v.delta = (bs.sampled_flags & bsdf_flags::Delta) != 0;
    v.eta = bs.eta;
    add_vertex(v);
}

}  // namespace volguide
