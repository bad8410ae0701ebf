#include "volguide/integrators/guided/walk/guided_vertex.h"

namespace volguide {

namespace {

// Adds what a distance decision reported to the walk's counters.
void count_distance(const DistanceReport& r, WalkGuideStats& counts) {
    using Method = DistanceReport::Method;
    counts.distance_outside_field += r.method == Method::OutsideField;
    counts.distance_queries += r.method == Method::Tracking || r.method == Method::Bins || r.method == Method::Vsp;
    counts.guided_tracking += r.method == Method::Tracking;
    counts.distance_steps += r.steps;
    counts.invalid_bins += r.invalid;
    counts.damped_bins += r.damped;
    counts.nan_fallbacks += r.nan_fallbacks;
    counts.guided_strategy += r.guided;
    counts.vsp_queries += r.method == Method::Vsp;
    counts.vsp_camera += r.camera;
    counts.vsp_unguided += r.unguided;
    counts.vsp_resampled += r.resampled;
    counts.vsp_scattered += r.scattered;
    counts.vsp_equiangular += r.equiangular;
}

}  // namespace

void GuidedVertex::init(const MediumInteraction& mi, int known_leaf) {
    const int reached = known_leaf >= 0 ? known_leaf : reached_;
    clear();
    mi_ = mi;
    active_ = true;
    handed_ = reached;
    ++counts_.vertices;
}

void GuidedVertex::clear() {
    if (found_ && leaf_ >= 0) hint_ = leaf_;
    active_ = false;
    reached_ = -1;  // a vertex not reached by the next distance decision is in no known leaf
    handed_ = -1;
    found_ = false;
    prepared_ = false;
    direction_guidable_ = false;
    direction_.reset();
}

int GuidedVertex::keep() {
    if (!active_) return -1;
    leaf();
    prepare_direction();
    kept_.push_back(Kept{leaf_, found_, prepared_, direction_guidable_, direction_});
    return int(kept_.size()) - 1;
}

void GuidedVertex::resume(const MediumInteraction& mi, int kept) {
    reached_ = -1;  // the copy's vertex was not reached by the last distance decision
    if (kept < 0) {
        init(mi);
        return;
    }
    const Kept& k = kept_[size_t(kept)];
    init(mi, k.leaf);
    leaf_ = k.leaf;
    found_ = k.found;
    prepared_ = k.prepared;
    direction_guidable_ = k.guidable;
    direction_ = k.direction;
    ++counts_.vertices_resumed;
}

int GuidedVertex::leaf() {
    if (!found_) {
        uint64_t descents = 0;
        leaf_ = guide_.prepared().leaf_at(mi_.p, handed_ >= 0 ? handed_ : hint_, descents);
        counts_.vertex_descents += descents;
        counts_.work.add(Work::Descent, descents);
        found_ = true;
        // The direction decision reads the leaf's lobes next (after the estimate's table lookup).
        if (leaf_ >= 0 && guide_.guides_direction() && !prepared_) guide_.prepared().prefetch_direction_lobes(leaf_);
    }
    return leaf_;
}

int GuidedVertex::origin_leaf(const DistanceQuery& query, bool needed) {
    if (active_) return leaf();
    if (!needed) return -1;
    uint64_t descents = 0;  // the camera's and surfaces' lookups are not the vertices' descents
    const int leaf = guide_.prepared().leaf_at(query.ray.o, -1, descents);
    counts_.work.add(Work::Descent, descents);
    return leaf;
}

DistanceInput GuidedVertex::distance_input(const DistanceQuery& query, float camera_guided) {
    const Allocation& allocation = guide_.allocation();
    DistanceInput in;
    in.field = phase_field(query.medium.phase());
    in.camera_guided = camera_guided;
    in.origin = origin_leaf(query, !allocation.empty() || guide_.settings().distance == DistanceGuiding::Vsp);
    TrustPoint at{DecisionKind::Distance};
    at.leaf = in.camera() ? -1 : in.origin;  // the camera buffer's P_G has no leaf to damp
    if (at.leaf >= 0) at.sigma_t = query.medium.eval(query.ray.o).sigma_t;
    // The allocation's share of the origin's cell. Guided null-collision tracking keeps the configured
    // share: its decision is a sequence of collisions whose mixture density the learning cannot weigh.
    if (!query.medium.tracks_null_collisions())
        at.learned = allocation.share(DecisionKind::Distance, guide_.selection_cell(in.origin),
                                      exploration_coin(query.ray.o, query.ray.d, 1), learning_);
    at.vertex = active_;
    in.share = guide_.trust().guided_share(at);
    return in;
}

FreeFlightSample GuidedVertex::sample_distance(const DistanceQuery& query, float camera_guided, Sampler& sampler,
                                               DecisionRecord* record) {
    const DistanceInput in = distance_input(query, camera_guided);
    // Skipped: the guided share would be small and the guided walk (a leaf lookup per bin) costs more
    // than it can return. Unselected: volpath's decision, nothing guided is paid for.
    counts_.distance_skipped += in.share.source == ShareSource::Skipped;
    counts_.distance_unselected += in.share.source == ShareSource::Unselected;
    const DistanceSampler& method = in.share.guided() ? guide_.distance() : guide_.free_flight();
    DistanceOutcome out;
    out.record.leaf = in.origin;  // the decision's cell, mixture or not
    const FreeFlightSample fs = method.sample(query, in, scratch_, sampler, out);
    count_distance(out.report, counts_);
    if (&method != &guide_.free_flight()) {
        counts_.work.add(Work::GuidedSegment);
        counts_.work.add(Work::Bin, out.report.steps);
    }
    reached_ = out.scattering;
    if (record) {
        *record = out.record;
        record->guidable = in.share.source == ShareSource::Unselected;
    }
    return fs;
}

float GuidedVertex::phase_probability(int index) {
    TrustPoint at{DecisionKind::Direction, index, mi_.coeffs.sigma_t};
    if (index >= 0)
        at.learned = guide_.allocation().share(DecisionKind::Direction, guide_.selection_cell(index),
                                               exploration_coin(mi_.p, mi_.wi, 2), learning_);
    const GuidedShare g = guide_.trust().guided_share(at);
    direction_guidable_ = g.source == ShareSource::Unselected;
    // Learned shares are damped by the confidence as configured ones are (a short pilot does not see
    // the heavy tails long walks in a dense medium get from a large guided share: densesphere read low
    // undamped; bench/RESULTS.md (issue 35)).
    counts_.direction_damped_vertices +=
        g.source == ShareSource::Skipped || (g.source == ShareSource::Configured && g.confidence < 1.f);
    counts_.direction_unselected += g.source == ShareSource::Unselected;
    return 1.f - g.share;
}

void GuidedVertex::prepare_direction() {
    if (prepared_) return;
    prepared_ = true;
    if (!guide_.guides_direction()) return;
    const int index = leaf();
    const float phase_prob = phase_probability(index);
    const PhaseFunction& phase = mi_.medium->phase();
    const GuidedDirectionSampler& s =
        direction_.emplace(guide_.settings().direction, index >= 0 ? guide_.prepared().direction_lobes(index) : LobeBlock(), phase,
                           phase_lobes(phase), mi_.wi, phase_prob);
    counts_.direction_unguided_vertices += !s.guided();
    ++counts_.vertex_mixtures;
    counts_.vertex_products += s.product() != nullptr;
    if (s.guided()) {
        const int lobes = guide_.prepared().direction_lobes(index).count;
        counts_.work.add(Work::LobePair, uint64_t(s.product() ? lobes * phase_lobes(phase).count : lobes));
    }
}

const PhaseField& GuidedVertex::phase_field(const PhaseFunction& phase) {
    if (&phase != field_phase_) {
        field_phase_ = &phase;
        field_ = guide_.prepared().phase(phase);
    }
    return field_;
}

const PhaseLobes& GuidedVertex::phase_lobes(const PhaseFunction& phase) {
    if (&phase != lobes_phase_) {
        lobes_phase_ = &phase;
        lobes_ = phase_field(phase).lobes;
        if (!lobes_) {  // a phase function of no medium the guide saw: prepared here, once per walk
            own_lobes_ = prepare_phase_lobes(hg_phase_vmm(phase.mean_cosine()));
            lobes_ = &own_lobes_;
        }
    }
    return *lobes_;
}

GuidedDirectionSampler::Sample GuidedVertex::sample_direction(Point2f u, float u_strategy) const {
    if (direction_) return direction_->sample(u, u_strategy);
    // Not guided: the phase function (the walk without a guide draws the same numbers as phase().sample).
    const PhaseSample ps = mi_.medium->phase().sample(mi_.wi, u);
    GuidedDirectionSampler::Sample s;
    s.wo = ps.wo;
    s.pdf = ps.pdf;
    s.weight = ps.weight;
    s.phase = ps.pdf > 0.f ? ps.weight * ps.pdf : 0.f;
    return s;
}

float GuidedVertex::direction_pdf(const Vec3f& wo) const {
    if (!direction_) return mi_.medium->phase().pdf(mi_.wi, wo);
    if (direction_->guided()) counts_.work.add(Work::GuideEval);
    return direction_->pdf(wo);
}

Color3 GuidedVertex::estimate(ContinuationStage stage, const Vec3f& w) {
    const int index = leaf();
    if (!guide_.trust().trusted(index, mi_.coeffs.sigma_t)) return Color3(0.f);
    counts_.work.add(Work::Estimate);
    const PhaseFunction& phase = mi_.medium->phase();
    // After the direction decision the full L~, although NEE took the direct light at x: the
    // continuation still collects the emitter hits MIS gives it (a sky), and the indirect part
    // alone under-estimated it.
    const PhaseField& at = phase_field(phase);
    return stage == ContinuationStage::Distance ? at.inscattered(index, w) : at.incident(index, w);
}

}  // namespace volguide
