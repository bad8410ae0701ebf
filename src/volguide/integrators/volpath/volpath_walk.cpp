#include "volguide/integrators/volpath/volpath_walk.h"

#include <algorithm>
#include <cmath>

#include "volguide/integrators/volume_nee.h"
#include "volguide/media/medium.h"
#include "volguide/render/bsdf.h"
#include "volguide/render/emitter.h"
#include "volguide/render/scene.h"

namespace volguide {

VolumeWalk::VolumeWalk(const Scene& scene, const VolPathSettings& settings, Sampler& sampler, WalkPolicy* policy,
                       PathRecorder* recorder)
    : scene_(scene),
      settings_(settings),
      policy_(policy),
      recorder_(recorder),
      records_decisions_(policy && recorder && recorder->records_decisions()),
      guide_distance_(policy && policy->guides_distance()),
      rng_(&sampler) {}

Color3 VolumeWalk::run(const Ray& camera_ray, const Medium* medium, bool from_sensor) {
    state_.ray = camera_ray;
    state_.medium = from_sensor ? scene_.sensor().medium() : medium;
    count(Work::CameraSample);
    if (policy_) count(Work::Policy);
    if (policy_) {
        state_.split_allowance = policy_->branch_budget();
        policy_->end_vertex();  // the camera ray leaves from no medium vertex
    }
    walk_branch();
    // The waiting branches of this camera sample, last made first.
    while (!stack_.empty()) {
        PendingBranch b = std::move(stack_.back());
        stack_.pop_back();
        state_ = b.state;
        branch_sampler_ = b.sampler;
        rng_ = &branch_sampler_;
        need_intersection_ = true;
        report_work();  // the last branch's tail is its own
        if (recorder_) recorder_->resume_branch(b.record_point);
        if (policy_) resume_policy_vertex(b);
        if (b.at_vertex && !scatter(b.vertex)) continue;  // the copy ended at its vertex
        walk_branch();
    }
    if (policy_) policy_->end_camera_sample(branches_);
    take_policy_work();
    report_work();
    if (recorder_) recorder_->end_camera_sample(branches_);
    return result_;
}

void VolumeWalk::resume_policy_vertex(const PendingBranch& b) {
    if (b.has_vertex)
        policy_->resume_vertex(b.vertex.mi, b.kept);
    else
        policy_->end_vertex();
}

void VolumeWalk::walk_branch() {
    while (!state_.throughput.is_black() && russian_roulette() && depth_ok(state_.depth)) {
        if (need_intersection_) {
            count(Work::Intersection);
            if (!scene_.intersect(state_.ray, si_)) si_ = miss_interaction(state_.ray);
            need_intersection_ = false;
        }
        if (state_.medium) {
            MediumVertex v;
            const Step step = medium_step(v);
            if (step == Step::End) return;
            if (step == Step::Scatter) {
                if (!at_medium_vertex(v)) return;
                continue;
            }
        }
        if (!surface_step()) return;
    }
}

bool VolumeWalk::russian_roulette() {
    WalkState& s = state_;
    if (s.depth <= settings_.rr_depth || s.depth == s.rr_depth_done) return true;
    s.rr_depth_done = s.depth;
    const float q = roulette_survival(settings_.rr_rule, s.throughput.max_value() * s.eta * s.eta);
    // The sample is drawn even when q = 1 (the bounded rule above weight 1), so that both rules
    // spend the same random numbers per depth.
    if (!(rng_->next_1d() < q)) return false;
    s.throughput *= 1.f / q;
    return true;
}

VolumeWalk::Step VolumeWalk::medium_step(MediumVertex& v) {
    const Medium& medium = *state_.medium;
    const float tmax = si_.is_valid() ? si_.t : state_.ray.tmax;
    if (settings_.equiangular && !guide_distance_ && medium.is_homogeneous() && medium.sample_emitters())
        return equiangular_step(medium, tmax, v);
    DecisionRecord record;
    const FreeFlightSample ff =
        policy_ ? policy_->sample_distance(DistanceQuery{medium, state_.ray, tmax, state_.throughput, state_.depth},
                                           *rng_, decision_record(record))
                : medium.sample_free_flight(state_.ray, tmax, state_.throughput, *rng_);
    record.own.add(Work::Segment);
    if (medium.tracks_null_collisions()) record.own.add(Work::Tracked);
    report_decision(DecisionKind::Distance, record);
    state_.throughput *= ff.weight;
    if (state_.throughput.is_black()) return Step::End;
    if (!ff.scattered) return Step::Surface;
    v.mi = ff.mi;
    if (!v.mi.medium) v.mi.medium = &medium;
    ++state_.depth;
    if (!depth_ok(state_.depth)) return Step::End;
    if (policy_) policy_->begin_vertex(v.mi);
    return Step::Scatter;
}

VolumeWalk::Step VolumeWalk::equiangular_step(const Medium& medium, float tmax, MediumVertex& v) {
    const MediumCoefficients mc = medium.eval(state_.ray.o);
    const EquiSegment seg = equiangular_segment(state_.ray, tmax, mc, state_.throughput);
    count(Work::Segment);
    // Strategy 3 (equiangular_mis.h), for paths one vertex longer.
    if (depth_ok(state_.depth + 1)) {
        count(Work::ShadowRay);
        if (const auto c = equiangular_light_sample(scene_, medium, seg, state_.throughput, *rng_)) add(*c);
    }
    // Strategies 1 and 2 start from the distance sampled here.
    const FreeFlightSample ff = equiangular_free_flight(state_.ray, seg, mc, &medium, *rng_, v.equi);
    state_.throughput *= ff.weight;
    if (state_.throughput.is_black()) return Step::End;
    if (!ff.scattered) return Step::Surface;
    v.mi = ff.mi;
    ++state_.depth;
    if (!depth_ok(state_.depth)) return Step::End;
    if (policy_) policy_->begin_vertex(v.mi);  // reached by no distance decision of the policy's
    return Step::Scatter;
}

bool VolumeWalk::at_medium_vertex(const MediumVertex& v) {
    // Distance-stage continuation: the vertex collects ~ L_i(x_j, w_{j-1}) from here on; every copy
    // does its own NEE and direction (docs/theory.md §9.3).
    if (policy_ && !continue_path(ContinuationStage::Distance, v, state_.ray.d)) return false;
    return scatter(v);
}

bool VolumeWalk::scatter(const MediumVertex& v) {
    const MediumInteraction& mi = v.mi;
    WalkState& s = state_;
    if (settings_.forward_first_scatter && s.depth == 1) {
        // Inspection: a forward delta phase function at the first vertex (weight 1).
        s.specular_chain = true;
        s.last_vertex = mi;
        s.last_equi.on = false;
        s.ray = mi.spawn_ray(s.ray.d);
        need_intersection_ = true;
        return true;
    }
    if (recorder_) recorder_->record_medium_hit(mi);
    count(Work::MediumVertex);
    // One direction sampler per vertex, used by NEE's MIS and the continuation.
    if (policy_) policy_->prepare_direction(mi, *rng_);
    if (mi.medium->sample_emitters()) {
        s.specular_chain = false;
        sample_nee_medium(v);
    } else {
        s.specular_chain = true;
    }
    DecisionRecord record;
    const PhaseSample ps = policy_ ? policy_->sample_direction(mi, *rng_, decision_record(record))
                                   : mi.medium->phase().sample(mi.wi, rng_->next_2d());
    report_decision(DecisionKind::Direction, record);
    if (!(ps.pdf > 0.f)) return false;
    s.throughput *= ps.weight;
    // Training sample at x_j: the radiance arriving from w_j is what guides w_j.
    if (recorder_) recorder_->record_medium_vertex(mi.p, ps.wo, ps.pdf, s.throughput);
    s.last_vertex = mi;
    s.last_pdf = ps.pdf;  // MIS uses p_w alone: the direction stage's q depends on w (§8.3, §13.11)
    s.last_equi = v.equi;
    s.ray = mi.spawn_ray(ps.wo);
    need_intersection_ = true;
    // Direction-stage continuation: the continuation along w_j collects ~ L(x_j, w_j).
    if (policy_ && !s.throughput.is_black()) return continue_path(ContinuationStage::Direction, v, ps.wo);
    return true;
}

void VolumeWalk::sample_nee_medium(const MediumVertex& v) {
    const MediumInteraction& mi = v.mi;
    const PhaseFunction& phase = mi.medium->phase();
    count(Work::ShadowRay);
    const VolumeEmitterSample es =
        sample_emitter_through_media(scene_, mi, nullptr, state_.medium, rng_->next_2d(), *rng_);
    if (es.weight.is_black()) return;
    const float fp = phase.eval(mi.wi, es.ds.d);
    const float pp =
        es.ds.delta ? 0.f : (policy_ ? policy_->direction_pdf(mi, es.ds.d) : phase.pdf(mi.wi, es.ds.d));
    const float w = equiangular_mis_applies(v.equi, es.ds) ? equiangular_nee_weight(scene_, mi, v.equi, es.ds, pp)
                    : es.ds.delta                         ? 1.f
                                                          : mis_power_heuristic(es.ds.pdf, pp);
    add(state_.throughput * fp * es.weight * w);
    if (recorder_) recorder_->record_medium_nee(mi.p, es.ds.d, es.weight * w);
}

bool VolumeWalk::surface_step() {
    WalkState& s = state_;
    // volume_only: a camera path whose first real event is not a medium scattering is excluded.
    if (settings_.volume_only && s.depth == 0 && !(si_.is_valid() && si_.shape->bsdf()->is_null())) return false;
    if (recorder_) recorder_->record_surface_hit(si_);
    emitter_hit();
    if (!si_.is_valid()) return false;

    const BSDF& bsdf = *si_.shape->bsdf();
    count(Work::SurfaceVertex);
    if (policy_) policy_->prepare_surface_direction(si_, bsdf, s.medium, *rng_);
    // NEE (only when its path, one segment longer, is within max_depth).
    if (bsdf.has(bsdf_flags::Smooth) && depth_ok(s.depth + 1)) sample_nee_surface(bsdf);

    const float u1 = rng_->next_1d();
    const Point2f u2 = rng_->next_2d();
    DecisionRecord record;
    const auto [bs, bsdf_weight] =
        policy_ ? policy_->sample_surface_direction(SurfaceQuery{ctx_, si_, bsdf}, u1, u2, *rng_, decision_record(record))
                : bsdf.sample(ctx_, si_, u1, u2);
    report_decision(DecisionKind::Surface, record);
    s.throughput *= bsdf_weight;
    if (s.throughput.is_black()) return false;
    s.eta *= bs.eta;
    const Vec3f wo = si_.to_world(bs.wo);
    if (recorder_) recorder_->record_surface_vertex(si_, bs, wo, s.throughput);
    if (bs.sampled_flags & bsdf_flags::Null) {
        if (++s.null_crossings > kMaxNullCrossings) return false;  // a ray stuck on a surface
    } else {
        ++s.depth;
        s.last_vertex = si_;
        s.last_pdf = bs.pdf;
        s.last_equi.on = false;
        s.specular_chain = (bs.sampled_flags & bsdf_flags::Delta) != 0;
    }
    s.medium = medium_after(si_, wo, s.medium);
    s.ray = si_.spawn_ray(wo);
    if (policy_) policy_->end_vertex();  // the ray leaves a surface: no medium vertex
    need_intersection_ = true;
    if (policy_ && (bs.sampled_flags & bsdf_flags::Diffuse) && policy_->decides_at_surfaces())
        return continue_at_surface(wo);
    return true;
}

bool VolumeWalk::continue_at_surface(const Vec3f& wo) {
    const ContinuationQuery query = continuation_query(ContinuationStage::Surface, wo);
    count(Work::Continuation);
    const Continuation c = policy_->surface_continuation(si_, query, *rng_);
    take_policy_work();
    return continue_copies(c, ContinuationStage::Surface, wo, nullptr);
}

void VolumeWalk::emitter_hit() {
    const WalkState& s = state_;
    const Emitter* emitter = si_.is_valid() ? si_.shape->emitter() : scene_.environment();
    if (!emitter || (s.depth == 0 && (settings_.hide_emitters || settings_.volume_only))) return;
    if (s.depth == 0 || s.specular_chain) {
        add(s.throughput * emitter->eval(si_));
        return;
    }
    const DirectionSample ds = emitter_hit_record(si_, s.last_vertex, s.ray.d, emitter);
    const float emitter_pdf = scene_.pdf_emitter_direction(s.last_vertex, ds);
    const float w = equiangular_mis_applies(s.last_equi, ds)
                        ? equiangular_hit_weight(scene_, s.last_equi, ds, s.last_pdf, emitter_pdf)
                        : mis_power_heuristic(s.last_pdf, emitter_pdf);
    add(s.throughput * emitter->eval(si_) * w);
}

void VolumeWalk::sample_nee_surface(const BSDF& bsdf) {
    count(Work::ShadowRay);
    const VolumeEmitterSample es =
        sample_emitter_through_media(scene_, si_, &si_, state_.medium, rng_->next_2d(), *rng_);
    if (es.weight.is_black()) return;
    const Vec3f wo = si_.to_local(es.ds.d);
    const Color3 f = bsdf.eval(ctx_, si_, wo);
    const float bsdf_pdf =
        es.ds.delta ? 0.f
                    : (policy_ ? policy_->surface_direction_pdf(SurfaceQuery{ctx_, si_, bsdf}, wo) : bsdf.pdf(ctx_, si_, wo));
    const float w = es.ds.delta ? 1.f : mis_power_heuristic(es.ds.pdf, bsdf_pdf);
    add(state_.throughput * f * es.weight * w);
}

bool VolumeWalk::continue_path(ContinuationStage stage, const MediumVertex& v, const Vec3f& w) {
    const ContinuationQuery query = continuation_query(stage, w);
    count(Work::Continuation);
    const Continuation c = policy_->continuation(query, v.mi, *rng_);
    take_policy_work();
    return continue_copies(c, stage, w, &v);
}

bool VolumeWalk::continue_copies(const Continuation& c, ContinuationStage stage, const Vec3f& w,
                                 const MediumVertex* vertex) {
    if (c.guided) state_.rr_depth_done = state_.depth;  // replaces throughput RR at this depth
    if (c.n == 0 && c.q != 1.f) return false;
    if (c.q != 1.f) state_.throughput *= 1.f / c.q;
    // The point is reported with its weight after the decision, before its copies (branch_point).
    if (records_decisions_) count(Work::Recorded);
    report_work();
    if (recorder_) recorder_->record_continuation(stage, c, w, state_.throughput);
    if (c.q == 1.f || c.n <= 1) return true;
    count(Work::Branch, uint64_t(c.n - 1));
    // The n copies share the path's allowance, so the live branches' allowances never sum to more
    // than the camera sample's budget.
    state_.split_allowance /= float(c.n);
    // A copy's vertex is resumed (resume_policy_vertex) with what the policy kept of it: its copies
    // find and build nothing again.
    const bool at_vertex = vertex && stage == ContinuationStage::Distance;
    const int kept = vertex && policy_ ? policy_->keep_vertex() : -1;
    for (int k = 1; k < c.n; ++k)
        stack_.push_back(PendingBranch{state_, rng_->fork(uint64_t(k)), at_vertex, vertex != nullptr,
                                       vertex ? *vertex : MediumVertex(), recorder_ ? recorder_->branch_point() : 0,
                                       kept});
    branches_ += c.n - 1;
    return true;
}

// The decision's own work is the walk's units it added to `record` and the policy's since its last
// decision; the work before it is reported first (it belongs to what was current then).
ContinuationQuery VolumeWalk::continuation_query(ContinuationStage stage, const Vec3f& w) const {
    const WalkState& s = state_;
    ContinuationQuery q{stage, w, s.throughput, branches_, s.split_allowance, records_decisions_};
    const float beta = s.throughput.max_value() * s.eta * s.eta;
    q.bound = std::min(1.f, beta);
    const bool plays = stage != ContinuationStage::Distance && s.depth > settings_.rr_depth && s.depth != s.rr_depth_done;
    q.roulette = plays ? roulette_survival(settings_.rr_rule, beta) : 1.f;
    return q;
}

void VolumeWalk::report_decision(DecisionKind kind, DecisionRecord& record) {
    if (policy_) record.own += policy_->take_work();
    if (records_decisions_) count(Work::Recorded);
    report_work();
    work_ += record.own;
    if (records_decisions_) recorder_->record_decision(kind, record);
}

void VolumeWalk::report_work() {
    if (pending_.empty()) return;
    work_ += pending_;
    if (recorder_) recorder_->record_work(pending_);
    pending_ = WorkCounts{};
}

void VolumeWalk::add(const Color3& c) {
    result_ += c;
    if (recorder_) recorder_->record_contribution(c);
}

}  // namespace volguide
