#include "volguide/integrators/guided/walk/guided_vertex.h"

namespace volguide {

void GuidedVertex::init(const MediumInteraction& mi, const VertexLeaf& handed) {
    clear();
    mi_ = mi;
    active_ = true;
    handed_ = handed.leaf;
    ++counts_.vertices;
}

void GuidedVertex::clear() {
    if (found_ && leaf_ >= 0) hint_ = leaf_;
    active_ = false;
    handed_ = -1;
    found_ = false;
    prepared_ = false;
    direction_.reset();
}

int GuidedVertex::keep() {
    if (!active_) return -1;
    leaf();
    prepare_direction();
    kept_.push_back(Kept{leaf_, found_, prepared_, direction_});
    return int(kept_.size()) - 1;
}

void GuidedVertex::resume(const MediumInteraction& mi, int kept) {
    if (kept < 0) {
        init(mi, VertexLeaf());
        return;
    }
    const Kept& k = kept_[size_t(kept)];
    init(mi, VertexLeaf{k.leaf});
    leaf_ = k.leaf;
    found_ = k.found;
    prepared_ = k.prepared;
    direction_ = k.direction;
    ++counts_.vertices_resumed;
}

int GuidedVertex::leaf() {
    if (!found_) {
        leaf_ = guide_.leaf_at(mi_.p, handed_ >= 0 ? handed_ : hint_, counts_.vertex_descents);
        found_ = true;
    }
    return leaf_;
}

int GuidedVertex::origin_leaf(const DistanceQuery& query, bool needed) {
    if (active_) return leaf();
    if (!needed) return -1;
    uint64_t descents = 0;  // the camera's and surfaces' lookups are not the vertices' descents
    return guide_.leaf_at(query.ray.o, -1, descents);
}

FreeFlightSample GuidedVertex::sample_distance(const DistanceQuery& query, Sampler& sampler, VertexLeaf& scattering,
                                               DecisionRecord* record) {
    DistanceContext& ctx = distance_;
    ctx.scattering = -1;
    ctx.record = DecisionRecord();
    ctx.unguided = guide_.settings().distance_settings.c_T;
    const DistanceSampler* method = &guide_.distance();
    // The learned selection's share of the origin's cell (the pilot records every cell's decisions).
    const bool select = guide_.selection().learned(SelectionDecision::Distance) || record;
    ctx.origin = origin_leaf(query, select || guide_.settings().distance == DistanceGuiding::Vsp);
    if (active_ && ctx.origin >= 0 &&
        guide_.confidence(ctx.origin, query.medium.eval(query.ray.o).sigma_t) < WalkGuide::kSkipConfidence) {
        // The guided share would be small and the guided walk (a leaf lookup per bin) costs more than
        // it can return: free flight.
        ++counts_.distance_skipped;
        method = &guide_.free_flight();
    } else if (select) {
        const float share = guide_.selection().share(SelectionDecision::Distance, guide_.selection_cell(ctx.origin));
        if (share == 0.f) {  // volpath's decision: nothing guided is paid for
            ++counts_.distance_unselected;
            method = &guide_.free_flight();
        } else if (share != LearnedSelection::kDefault) {
            ctx.unguided = 1.f - share;
        }
    }
    ctx.record.leaf = ctx.origin;  // the decision's cell, mixture or not
    const FreeFlightSample fs = method->sample(query, ctx, sampler, counts_);
    scattering.leaf = ctx.scattering;
    if (record) *record = ctx.record;
    return fs;
}

float GuidedVertex::phase_probability(int index) {
    const float configured = guide_.settings().phase_prob;
    if (index < 0) return configured;
    const float confidence = guide_.confidence(index, mi_.coeffs.sigma_t);
    const float share = guide_.selection().share(SelectionDecision::Direction, guide_.selection_cell(index));
    if (confidence < WalkGuide::kSkipConfidence) {  // the product is not worth building: the phase function alone
        ++counts_.direction_damped_vertices;
        return 1.f;
    }
    if (share != LearnedSelection::kDefault) {
        // Learned: the share replaces the configured one, damped by the confidence as that is (a
        // short pilot does not see the heavy tails long walks in a dense medium get from a large
        // guided share: densesphere read low undamped; bench/RESULTS.md (issue 35)).
        if (share == 0.f) ++counts_.direction_unselected;
        return 1.f - share * confidence;
    }
    if (confidence < 1.f) {
        ++counts_.direction_damped_vertices;
        return 1.f - (1.f - configured) * confidence;
    }
    return configured;
}

void GuidedVertex::prepare_direction() {
    if (prepared_) return;
    prepared_ = true;
    if (!guide_.guides_direction()) return;
    const int index = leaf();
    const float phase_prob = phase_probability(index);
    const PhaseFunction& phase = mi_.medium->phase();
    const GuidedDirectionSampler& s =
        direction_.emplace(guide_.settings().direction, index >= 0 ? guide_.direction_lobes(index) : LobeBlock(), phase,
                           phase_lobes(phase), mi_.wi, phase_prob);
    counts_.direction_unguided_vertices += !s.guided();
    ++counts_.vertex_mixtures;
    counts_.vertex_products += s.product() != nullptr;
}

const PhaseLobes& GuidedVertex::phase_lobes(const PhaseFunction& phase) {
    if (&phase != lobes_phase_) {
        lobes_phase_ = &phase;
        lobes_ = guide_.phase_lobes(phase);
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
    return direction_ ? direction_->pdf(wo) : mi_.medium->phase().pdf(mi_.wi, wo);
}

Color3 GuidedVertex::estimate(ContinuationStage stage, const Vec3f& w) {
    const int index = leaf();
    if (index < 0 || guide_.confidence(index, mi_.coeffs.sigma_t) < WalkGuide::kSkipConfidence) return Color3(0.f);
    const PhaseFunction& phase = mi_.medium->phase();
    // After the direction decision the full L~, although NEE took the direct light at x: the
    // continuation still collects the emitter hits MIS gives it (a sky), and the indirect part
    // alone under-estimated it.
    return stage == ContinuationStage::Distance ? guide_.inscattered(index, phase, w) : guide_.incident(index, phase, w);
}

}  // namespace volguide
