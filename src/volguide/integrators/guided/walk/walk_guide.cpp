#include "volguide/integrators/guided/walk/walk_guide.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "volguide/integrators/guided/walk/distance_bins.h"
#include "volguide/integrators/guided/walk/guided_vertex.h"
#include "volguide/integrators/guided/walk/vsp_distance.h"
#include "volguide/guiding/guided_collision.h"
#include "volguide/guiding/surface_guide.h"
#include "volguide/media/majorant_tracking.h"
#include "volguide/media/spectral_mis.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensor.h"
#include "volguide/vmm/phase_vmm.h"

namespace volguide {

WalkGuideStats& WalkGuideStats::operator+=(const WalkGuideStats& o) {
#define VOLGUIDE_WALK_GUIDE_ADD(member, name, of) member += o.member;
    VOLGUIDE_WALK_GUIDE_COUNTERS(VOLGUIDE_WALK_GUIDE_ADD)
#undef VOLGUIDE_WALK_GUIDE_ADD
    return *this;
}

std::vector<std::pair<std::string, double>> WalkGuideStats::named() const {
    auto ratio = [](uint64_t a, uint64_t b) { return b ? double(a) / double(b) : 0.0; };
#define VOLGUIDE_WALK_GUIDE_NAMED(member, name, of) {name, ratio(member, uint64_t(of))},
    return {VOLGUIDE_WALK_GUIDE_COUNTERS(VOLGUIDE_WALK_GUIDE_NAMED)};
#undef VOLGUIDE_WALK_GUIDE_NAMED
}

WalkGuide::WalkGuide(const Scene& scene, const GuidingField& field, const WalkGuideSettings& settings)
    : scene_(scene), field_(field), settings_(settings) {
    if (settings_.direction_indirect) {
        direction_leaves_.resize(field.leaves().size());
        for (size_t i = 0; i < field.leaves().size(); ++i) {
            GuidingLeaf& d = direction_leaves_[i];
            d.vmm = field.leaves()[i].vmm_indirect;
            d.valid = field.leaves()[i].valid_indirect;
            d.fluence = field.leaves()[i].fluence;
            d.samples = field.leaves()[i].samples;
        }
    }
    leaf_extent_ = leaf_extents(field.tree());  // before the groups, which read it
    auto add = [&](const Medium* m) {
        if (!m) return;
        const float g = m->phase().mean_cosine();
        if (!inscatter_.count(g)) inscatter_.emplace(g, InscatterCache(field, hg_phase_vmm(g)));
        if (!phase_vmms_.count(g)) phase_vmms_.emplace(g, hg_phase_vmm(g));
        if (!estimates_.count(g) && settings_.distance != DistanceGuiding::Standard)
            estimates_.emplace(std::piecewise_construct, std::forward_as_tuple(g),
                               std::forward_as_tuple(field, inscatter_.at(g), settings_.estimate_table));
        if (!groups_.count(g) && estimates_.count(g) && settings_.distance_merge > 0.f && settings_.estimate_table > 0)
            groups_.emplace(std::piecewise_construct, std::forward_as_tuple(g),
                             std::forward_as_tuple(field.tree(), estimates_.at(g), leaf_extent_,
                                                   settings_.distance_merge));
    };
    add(scene.sensor().medium());
    for (const auto& shape : scene.shapes()) {
        add(shape->interior_medium());
        add(shape->exterior_medium());
    }
}

float WalkGuide::leaf_confidence(int leaf, const Color3& sigma_t) const {
    if (leaf < 0) return 1.f;
    return volguide::leaf_confidence(leaf_extent_[size_t(leaf)], sigma_t, settings_.leaf_tau_max);
}

const LeafEstimates* WalkGuide::estimates_for(const PhaseFunction& phase) const {
    const auto it = estimates_.find(phase.mean_cosine());
    return it == estimates_.end() ? nullptr : &it->second;
}

const LeafGroups* WalkGuide::groups_for(const PhaseFunction& phase) const {
    const auto it = groups_.find(phase.mean_cosine());
    return it == groups_.end() ? nullptr : &it->second;
}

size_t WalkGuide::leaf_group_count() const {
    size_t n = 0;
    for (const auto& [g, r] : groups_) n += size_t(r.group_count());
    return n;
}

namespace {
// The walk's distance decision for a method of the learned selection's per-cell choice (selection.h):
// bins are the incremental sampler's (issue 37); `configured` where the cell has no learned method.
DistanceGuiding selected_method(uint8_t method, DistanceGuiding configured) {
    switch (method) {
        case uint8_t(DistanceMethod::FreeFlight): return DistanceGuiding::Standard;
        case uint8_t(DistanceMethod::Vsp): return DistanceGuiding::Vsp;
        case uint8_t(DistanceMethod::VspProduct): return DistanceGuiding::VspProduct;
        case uint8_t(DistanceMethod::Bins): return DistanceGuiding::Incremental;
        default: return configured;
    }
}
}  // namespace

FreeFlightSample WalkGuide::sample_distance(const Medium& medium, const Ray& ray, float tmax,
                                            const Color3& throughput, Sampler& sampler, GuidedVertex* from,
                                            VertexLeaf& vertex_leaf, DistanceScratch& scratch) const {
    // A query from a vertex whose leaf a decision there knows (GuidedVertex::known_leaf). Where that
    // leaf's confidence is below kSkipConfidence the guided share would be small, and the guided walk
    // (a leaf lookup per bin) costs more than it can return: free flight, as for leaves without
    // estimates.
    const int origin_leaf = from ? from->known_leaf() : -1;
    vertex_leaf.leaf = -1;
    scratch.decision = DistanceScratch::Decision();
    // The origin's leaf, kept on the free-flight paths below where the scattering vertex is in it
    // (deep in a dense medium it usually is): the direction decision there needs no descent.
    auto free_flight_from = [&](int origin) {
        scratch.decision.leaf = origin;
        FreeFlightSample fs = medium.sample_free_flight(ray, tmax, throughput, sampler);
        if (origin >= 0 && fs.scattered && field_.tree().holds_point(origin, fs.mi.p)) vertex_leaf.leaf = origin;
        return fs;
    };
    if (origin_leaf >= 0 && leaf_confidence(origin_leaf, medium.eval(ray.o).sigma_t) < kSkipConfidence) {
        ++stats_.local().distance_skipped;
        return free_flight_from(origin_leaf);
    }
    // Learned selection: the guided share and the method of the origin's selection cell (found by a
    // descent when no decision before found it); share 0 or the free-flight method: volpath's
    // decision, nothing guided is paid for (no table lookup, no bins, no product).
    int origin = origin_leaf;
    float c_T = settings_.distance_settings.c_T;
    DistanceGuiding method = settings_.distance;
    // (Only when some distance share was learned or the pilot records: heterogeneous media under
    // guided tracking record none, and a descent per decision would then be work for nothing.)
    if (selection_.learned(SelectionDecision::Distance) || scratch.record) {
        if (origin < 0) origin = from ? from->origin_leaf() : leaf_of(ray.o, VertexLeaf());
        const size_t cell = selection_cell(origin);
        const float share = selection_.share(SelectionDecision::Distance, cell);
        method = selected_method(selection_.distance_method(cell), method);
        if (share == 0.f || method == DistanceGuiding::Standard) {
            ++stats_.local().distance_unselected;
            return free_flight_from(origin);
        }
        if (share != LearnedSelection::kDefault) c_T = 1.f - share;
    }
    return guided_distance(method, medium, ray, tmax, origin, from, c_T, throughput, sampler, vertex_leaf, scratch);
}

FreeFlightSample WalkGuide::guided_distance(DistanceGuiding method, const Medium& medium, const Ray& ray, float tmax,
                                            int origin, GuidedVertex* from, float c_T, const Color3& throughput,
                                            Sampler& sampler, VertexLeaf& vertex_leaf, DistanceScratch& scratch) const {
    if (method == DistanceGuiding::Vsp || method == DistanceGuiding::VspProduct) {
        if (origin < 0) origin = from ? from->origin_leaf() : leaf_of(ray.o, VertexLeaf());
        scratch.decision.leaf = origin;
        const bool product = method == DistanceGuiding::VspProduct;
        if (!medium.is_homogeneous())
            return vsp_resampled(medium, ray, tmax, origin, from, c_T, product, throughput, sampler, vertex_leaf,
                                 scratch);
        return vsp_distance(medium, ray, tmax, origin, from, c_T, product, throughput, sampler, vertex_leaf, scratch);
    }
    scratch.decision.leaf = origin;
    float b0, b1;
    const bool crosses = !field_.empty() && field_.tree().bounds().ray_intersect(ray, b0, b1) && b1 > 0.f;
    // The guided part: (0, t_end); beyond the field's bounds the medium's own free flight.
    const float t_end = crosses ? std::min(tmax, b1) : 0.f;
    if (!(t_end > 0.f) || !std::isfinite(t_end)) {
        ++stats_.local().distance_outside_field;
        return medium.sample_free_flight(ray, tmax, throughput, sampler);
    }

    const LeafEstimates* estimates = estimates_for(medium.phase());
    if (method == DistanceGuiding::Incremental && settings_.guided_tracking && medium.tracks_null_collisions()) {
        // The whole segment: beyond the field the tracking falls back to the unguided probability.
        GuidedCollisionProbability guide(field_, estimates, ray, t_end, c_T);
        FreeFlightSample fs = guided_tracking(medium, ray, tmax, throughput, sampler, guide);
        WalkGuideStats& st = stats_.local();
        ++st.distance_queries;
        ++st.guided_tracking;
        st.distance_steps += guide.collisions();
        st.invalid_bins += guide.unguided_collisions();
        st.nan_fallbacks += guide.nan_fallbacks();
        scratch.decision.lookups = uint32_t(guide.collisions());
        return fs;
    }

    FreeFlightSample fs = binned_distance(method, medium, ray, tmax, t_end, estimates, c_T, throughput, sampler,
                                          vertex_leaf, scratch);
    scratch.decision.leaf = origin;
    return fs;
}

float WalkGuide::inscattered_along(const PhaseFunction& phase, const Ray& ray, float t, const Color3& sigma_t,
                                   int& hint, uint32_t& lookups) const {
    const Point3f x = ray(t);
    if (!(hint >= 0 && field_.tree().holds_point(hint, x))) {
        hint = field_.tree().leaf_at(x);
        ++lookups;  // the descent
    }
    if (hint < 0) return 0.f;
    ++lookups;
    // Damped by the leaf's confidence as the other guided decisions are (WalkGuideSettings::leaf_tau_max):
    // an optically large leaf's one estimate says little about one point in it, and following it made
    // fireflies in densesphere (bench/RESULTS.md, issue 37 deliverable 4).
    const float Li = leaf_inscattered(hint, phase, ray.d).average() * leaf_confidence(hint, sigma_t);
    return std::isfinite(Li) && Li > 0.f ? Li : 0.f;
}

float WalkGuide::product_floor(int origin, const PhaseFunction& phase, const Vec3f& d) const {
    // A fraction of the origin's own estimates: every candidate keeps a chance (exact weights
    // need target > 0 wherever a candidate carries weight), and where the field says the segment is
    // dark the target falls back to the conditional density alone.
    const float Li = origin >= 0 ? leaf_inscattered(origin, phase, d).average() : 0.f;
    if (std::isfinite(Li) && Li > 0.f) return kProductFloor * Li;
    const float L = origin >= 0 ? leaf_incident(origin, phase, d).average() : 0.f;
    return std::isfinite(L) && L > 0.f ? kProductFloor * L : 1.f;
}

float WalkGuide::origin_scatter_probability(GuidedVertex* from, int origin, const PhaseFunction& phase, const Ray& ray,
                                            float albedo, float unguided) const {
    // The vertex object's origin leaf is `origin` (both: the known leaf, else the one at ray.o = its point).
    return from ? from->scatter_probability(ray.d, albedo, unguided)
                : guided_scatter_probability(origin, phase, ray.d, albedo, unguided);
}

FreeFlightSample WalkGuide::vsp_distance(const Medium& medium, const Ray& ray, float tmax, int origin,
                                         GuidedVertex* from, float c_T, bool product, const Color3& throughput,
                                         Sampler& sampler, VertexLeaf& vertex_leaf, DistanceScratch& scratch) const {
    const MediumCoefficients at_origin = medium.eval(ray.o);
    const HomogeneousVsp vsp(at_origin.sigma_t, tmax, channel_probabilities(throughput));
    const float st = at_origin.sigma_t.average();
    const float albedo = st > 0.f ? at_origin.sigma_s.average() / st : 0.f;  // shapes P_G only
    // A camera segment's P_G from the per-pixel buffer (§7.10.2), else the origin leaf's lookup.
    const bool camera = !std::isnan(scratch.camera_guided);
    const float guided = camera ? scratch.camera_guided
                                : origin_scatter_probability(from, origin, medium.phase(), ray, albedo, vsp.unguided());
    scratch.decision.lookups = camera ? 0 : 1;
    WalkGuideStats& stats = stats_.local();
    ++stats.distance_queries;
    ++stats.vsp_queries;
    stats.vsp_camera += camera;
    if (std::isnan(guided)) {
        ++stats.vsp_unguided;
        return medium.sample_free_flight(ray, tmax, throughput, sampler);  // the same decision, unguided
    }
    const float P = vsp.probability(guided, vsp_unguided_share(origin, at_origin.sigma_t, c_T, camera));
    VspEquiangular equi;
    std::optional<EquiangularSampler> toward_light;
    HomogeneousVsp::Sample vs;
    if (product) {
        ++stats.vsp_product;
        vs = vsp_product_sample(vsp, P, medium, ray, origin, at_origin.sigma_t, sampler, scratch.decision.lookups);
    } else {
        const float u_decide = sampler.next_1d(), u_channel = sampler.next_1d(), u_t = sampler.next_1d();
        // The equiangular share (§7.10.1): a light point drawn only for a scatter (2 numbers).
        if (u_decide < P && settings_.vsp_equiangular > 0.f && medium.sample_emitters())
            toward_light = vsp_equiangular_toward_light(scene_, ray, tmax, sampler);
        equi = VspEquiangular{toward_light ? &*toward_light : nullptr, settings_.vsp_equiangular};
        vs = vsp.sample(P, u_decide, u_channel, u_t, equi);
        stats.vsp_equiangular += vs.scattered && equi.active();
    }
    FreeFlightSample fs;
    fs.t = vs.t;
    fs.weight = fs.flight_weight = vs.flight_weight;
    if (vs.scattered) {
        ++stats.vsp_scattered;
        const Point3f p = ray(vs.t);
        fs.scatter_at(ray, vs.t, p, &medium, medium.eval(p));
        fs.weight = fs.flight_weight * fs.mi.coeffs.sigma_s;
        if (field_.tree().holds_point(origin, p)) vertex_leaf.leaf = origin;
    }
    // The mixture's parts for the selection pilot: the density (or probability) of the outcome
    // under the unguided and the guided decision (not for the product's resampled distance, which
    // has no closed-form density).
    const float cond = vs.scattered ? vsp.conditional_pdf(vs.t, equi) : 1.f;
    const float pu = vs.scattered ? vsp.unguided() * cond : 1.f - vsp.unguided();
    const float pg = vs.scattered ? guided * cond : 1.f - guided;
    if (!product && vs.pdf > 0.f && P < 1.f) scratch.decision = {true, origin, vs.pdf, pu, pg, scratch.decision.lookups};
    return fs;
}

WalkGuide::ProductTarget::ProductTarget(const WalkGuide& guide, const PhaseFunction& phase, const Ray& ray, int origin,
                                        const Color3& sigma_t, uint32_t& lookups)
    : guide_(guide), phase_(phase), ray_(ray), sigma_t_(sigma_t), lookups_(lookups), hint_(origin),
      floor_(guide.product_floor(origin, phase, ray.d)) {
    lookups_ += 2;  // the floor's
}

float WalkGuide::ProductTarget::operator()(float t) {
    return guide_.inscattered_along(phase_, ray_, t, sigma_t_, hint_, lookups_) + floor_;
}

HomogeneousVsp::Sample WalkGuide::vsp_product_sample(const HomogeneousVsp& vsp, float P, const Medium& medium,
                                                     const Ray& ray, int origin, const Color3& sigma_t,
                                                     Sampler& sampler, uint32_t& lookups) const {
    ProductTarget target(*this, medium.phase(), ray, origin, sigma_t, lookups);
    return vsp.sample_resampled(P, settings_.product_candidates, target, sampler);
}

float WalkGuide::vsp_unguided_share(int origin, const Color3& sigma_t, float c_T, bool camera) const {
    // Defensive: the unguided share at least kVspMinUnguided, raised by a leaf of low confidence
    // as the bins' guided share is lowered (WalkGuideSettings::leaf_tau_max).
    const float confidence = camera ? 1.f : leaf_confidence(origin, sigma_t);
    return std::max(1.f - (1.f - c_T) * confidence, kVspMinUnguided);
}

FreeFlightSample WalkGuide::vsp_resampled(const Medium& medium, const Ray& ray, float tmax, int origin,
                                          GuidedVertex* from, float c_T, bool product, const Color3& throughput,
                                          Sampler& sampler, VertexLeaf& vertex_leaf, DistanceScratch& scratch) const {
    // The albedo field at the origin (the extinction there may be 0 on the medium's boundary).
    const float albedo = medium.albedo(ray.o).average();  // shapes P_G only
    const PhaseFunction& phase = medium.phase();
    const bool camera = !std::isnan(scratch.camera_guided);
    WalkGuideStats& stats = stats_.local();
    ++stats.distance_queries;
    ++stats.vsp_queries;
    stats.vsp_camera += camera;
    scratch.decision.lookups = camera ? 0 : 1;
    if (!camera && std::isnan(origin_scatter_probability(from, origin, phase, ray, albedo, 1.f))) {
        ++stats.vsp_unguided;
        return medium.sample_free_flight(ray, tmax, throughput, sampler);
    }
    ++stats.vsp_resampled;
    const Color3 sigma_origin = medium.eval(ray.o).sigma_t;  // the confidences' (shapes P and the target only)
    const float c = vsp_unguided_share(origin, sigma_origin, c_T, camera);
    uint32_t& lookups = scratch.decision.lookups;
    auto probability = [&](float unguided) {
        if (camera) return c * unguided + (1.f - c) * scratch.camera_guided;
        ++lookups;
        const float guided = origin_scatter_probability(from, origin, phase, ray, albedo, unguided);
        return std::isnan(guided) ? unguided : c * unguided + (1.f - c) * guided;
    };
    FreeFlightSample fs;
    if (product) {
        ++stats.vsp_product;
        ProductTarget target_of(*this, phase, ray, origin, sigma_origin, lookups);
        const SegmentTarget target(target_of);
        fs = resampled_segment_flight(medium, ray, tmax, throughput, probability, sampler, &target);
    } else {
        fs = resampled_segment_flight(medium, ray, tmax, throughput, probability, sampler);
    }
    if (fs.scattered) {
        ++stats.vsp_scattered;
        if (field_.tree().holds_point(origin, fs.mi.p)) vertex_leaf.leaf = origin;
    }
    return fs;
}

FreeFlightSample WalkGuide::binned_distance(DistanceGuiding method, const Medium& medium, const Ray& ray, float tmax, float t_end,
                                            const LeafEstimates* estimates, float c_T, const Color3& throughput,
                                            Sampler& sampler, VertexLeaf& vertex_leaf, DistanceScratch& scratch) const {
    DistanceScratch& s = scratch;
    GuidedDistanceSettings distance_settings = settings_.distance_settings;
    distance_settings.c_T = c_T;
    distance_settings.channel_split = channel_probabilities(throughput);  // spectral MIS (§2.6)
    const LeafGroups* groups = groups_for(medium.phase());
    BinSource source(ray, t_end, medium, field_, estimates, s.proxies, settings_.max_bin_optical_depth,
                     leaf_extent_, settings_.leaf_tau_max, groups);
    DistanceSample ds;
    if (method == DistanceGuiding::Incremental) {
        ds = sample_incremental_distance(source, sampler, distance_settings);
    } else {
        s.bins.clear();
        DistanceBin bin;
        while (source(bin)) s.bins.push_back(bin);
        const TabulatedDistance table(s.bins, std::nullopt, distance_settings);
        ds = table.sample(sampler);
        ds.steps = int(s.bins.size());
    }

    WalkGuideStats& st = stats_.local();
    ++st.distance_queries;
    st.distance_steps += uint64_t(ds.steps);
    st.guided_strategy += ds.strategy == DistanceStrategy::Guided;
    st.invalid_bins += source.invalid();
    st.damped_bins += source.damped();
    st.nan_fallbacks += uint64_t(ds.nan_fallbacks);
    s.decision.lookups = uint32_t(std::max(0, ds.steps));
    if (ds.event == DistanceEvent::Medium && ds.pdf > 0.f)
        vertex_leaf.leaf = groups && source.leaf() >= 0 ? groups->fine_leaf(source.leaf(), ray(ds.t)) : source.leaf();
    if (ds.pdf > 0.f && ds.pdf_transmittance >= 0.f && ds.pdf_guided >= 0.f) {
        s.decision.mixture = true;
        s.decision.pdf = ds.pdf;
        s.decision.p_u = ds.pdf_transmittance;
        s.decision.p_g = ds.pdf_guided;
    }
    return binned_flight(medium, ray, tmax, t_end, ds, throughput, sampler);
}

FreeFlightSample WalkGuide::binned_flight(const Medium& medium, const Ray& ray, float tmax, float t_end,
                                          const DistanceSample& ds, const Color3& throughput, Sampler& sampler) const {
    FreeFlightSample fs;
    if (ds.event == DistanceEvent::Medium && ds.pdf > 0.f) {
        const float t = ds.t;
        const Color3 tr = medium.transmittance(ray, t, sampler);
        const Point3f p = ray(t);
        fs.scatter_at(ray, t, p, &medium, medium.eval(p));
        fs.flight_weight = tr * (1.f / ds.pdf);
        fs.weight = fs.flight_weight * fs.mi.coeffs.sigma_s;
        return fs;
    }
    if (ds.event == DistanceEvent::Medium || !(ds.pdf > 0.f)) {  // a zero pdf cannot be weighted: no path
        fs.weight = fs.flight_weight = Color3(0.f);
        fs.t = t_end;
        return fs;
    }
    const Color3 tr = medium.transmittance(ray, t_end, sampler);
    fs.weight = fs.flight_weight = tr * (1.f / ds.pdf);
    fs.t = t_end;
    if (t_end < tmax) {
        // Beyond the field: continue with ordinary free flight from the exit point.
        const Ray rest(ray(t_end), ray.d);
        FreeFlightSample tail =
            medium.sample_free_flight(rest, tmax - t_end, throughput * fs.weight, sampler);
        tail.weight *= fs.weight;
        tail.flight_weight *= fs.weight;
        tail.t += t_end;
        if (tail.scattered) {
            tail.mi.t = tail.t;
            tail.mi.wi = -ray.d;
        }
        return tail;
    }
    return fs;
}

void WalkGuide::direction_sampler(const MediumInteraction& mi, const PhaseFunction& phase, int index,
                                  std::optional<GuidedDirectionSampler>& out) const {
    const GuidingLeaf* leaf = nullptr;
    if (index >= 0) leaf = settings_.direction_indirect ? &direction_leaves_[size_t(index)] : &field_.leaves()[size_t(index)];
    const auto it = phase_vmms_.find(phase.mean_cosine());
    float phase_prob = settings_.phase_prob;
    if (leaf) {
        const float confidence = leaf_confidence(index, mi.coeffs.sigma_t);
        const float share = selection_.share(SelectionDecision::Direction, size_t(index));
        if (confidence < kSkipConfidence) {
            // The product is not worth building: the phase function alone.
            phase_prob = 1.f;
            ++stats_.local().direction_damped_vertices;
        } else if (share != LearnedSelection::kDefault) {
            // Learned: the share replaces the configured one, damped by the confidence as that
            // is (a short pilot does not see the heavy tails long walks in a dense medium get
            // from a large guided share: densesphere read low undamped; bench/RESULTS.md (issue 35)).
            phase_prob = 1.f - share * confidence;
            if (share == 0.f) ++stats_.local().direction_unselected;
        } else if (confidence < 1.f) {
            phase_prob = 1.f - (1.f - phase_prob) * confidence;
            ++stats_.local().direction_damped_vertices;
        }
    }
    const GuidedDirectionSampler& s = out.emplace(settings_.direction, leaf, phase, mi.wi, phase_prob,
                                                  it == phase_vmms_.end() ? nullptr : &it->second);
    if (!s.guided()) ++stats_.local().direction_unguided_vertices;
}

int WalkGuide::surface_sampler(const SurfaceInteraction& si, const BSDF& bsdf, const Medium* medium,
                               Vmm& guide_storage, std::optional<GuidedSurfaceSampler>& out) const {
    const Vmm* guide = nullptr;
    float bsdf_prob = settings_.bsdf_prob;
    int index = -1;
    if (guides_surfaces() && !field_.empty() && bsdf.flags() == bsdf_flags::DiffuseReflection) {
        ++stats_.local().surface_vertices;
        const SurfaceLeaf beside = surface_leaf(field_, si);
        index = beside.leaf;
        const float share = index >= 0 ? selection_.share(SelectionDecision::Surface, size_t(index))
                                       : LearnedSelection::kDefault;
        const GuidingLeaf* leaf = nullptr;
        if (index >= 0)
            leaf = settings_.direction_indirect ? &direction_leaves_[size_t(index)] : &field_.leaves()[size_t(index)];
        const float confidence = leaf && medium ? leaf_confidence(index, medium->eval(si.p).sigma_t) : 1.f;
        const bool guidable = leaf && leaf->valid && leaf->vmm.count > 0 && confidence >= kSkipConfidence &&
                              field_.leaves()[size_t(index)].mostly_medium();
        if (guidable && share == 0.f) {
            ++stats_.local().surface_unselected;  // only vertices the configured mixture would guide
        } else if (guidable) {
            bsdf_prob = 1.f - (share != LearnedSelection::kDefault ? share : 1.f - bsdf_prob) * confidence;
            if (settings_.direction == DirectionGuiding::Incident)
                guide = &leaf->vmm;
            else if (cosine_product(leaf->vmm, beside.n, guide_storage))
                guide = &guide_storage;
        }
    }
    out.emplace(bsdf, si, guide, bsdf_prob);
    if (out->guided()) ++stats_.local().surface_guided_vertices;
    return index;
}

void WalkGuide::count_rrs_unselected() const { ++stats_.local().rrs_unselected; }

std::array<float, kSelectionDecisions> WalkGuide::configured_shares() const {
    return {1.f - settings_.distance_settings.c_T, 1.f - settings_.phase_prob, 1.f - settings_.bsdf_prob};
}

int WalkGuide::leaf_of(const Point3f& x, const VertexLeaf& vertex_leaf) const {
    if (field_.empty()) return -1;
    if (vertex_leaf.leaf >= 0 && field_.tree().holds_point(vertex_leaf.leaf, x)) return vertex_leaf.leaf;
    return field_.tree().leaf_at(x);
}

int WalkGuide::vertex_leaf_of(const Point3f& x, int hint) const {
    if (field_.empty()) return -1;
    if (hint >= 0 && field_.tree().holds_point(hint, x)) return hint;
    ++stats_.local().vertex_descents;
    return field_.tree().leaf_at(x);
}

int WalkGuide::trusted_leaf(int leaf, const Color3& sigma_t) const {
    if (leaf < 0) return -1;
    return leaf_confidence(leaf, sigma_t) < kSkipConfidence ? -1 : leaf;
}

void WalkGuide::count_vertex() const { ++stats_.local().vertices; }

void WalkGuide::count_vertex_mixture(bool product) const {
    WalkGuideStats& st = stats_.local();
    ++st.vertex_mixtures;
    st.vertex_products += product;
}

void WalkGuide::count_vertex_distance_kill() const { ++stats_.local().vertex_distance_kills; }

Color3 WalkGuide::leaf_inscattered(int leaf, const PhaseFunction& phase, const Vec3f& d) const {
    // The distance decisions' tables when they exist (one bilinear lookup instead of K x J lobes).
    if (const LeafEstimates* tables = estimates_for(phase)) {
        Color3 Li(0.f), L(0.f);
        tables->lookup(leaf, d, Li, L);
        return Li;
    }
    const auto it = inscatter_.find(phase.mean_cosine());
    return it == inscatter_.end() ? Color3(0.f) : it->second.inscattered(leaf, d);
}

Color3 WalkGuide::leaf_incident(int leaf, const PhaseFunction& phase, const Vec3f& w) const {
    if (const LeafEstimates* tables = estimates_for(phase)) {  // L~ looking ahead along w
        Color3 Li(0.f), L(0.f);
        tables->lookup(leaf, w, Li, L);
        return L;
    }
    return GuidingField::incident(field_.leaves()[size_t(leaf)], w);
}

float WalkGuide::guided_scatter_probability(int leaf, const PhaseFunction& phase, const Vec3f& w, float albedo,
                                            float unguided) const {
    constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
    if (leaf < 0) return kNone;
    Color3 Li(0.f), L(0.f);
    if (const LeafEstimates* tables = estimates_for(phase)) {
        if (!tables->lookup(leaf, w, Li, L)) return kNone;
    } else {
        Li = leaf_inscattered(leaf, phase, w);
        L = leaf_incident(leaf, phase, w);
    }
    const float scatter = albedo * unguided * Li.average(), total = L.average();
    if (!(scatter > 0.f)) return scatter == 0.f && total > 0.f ? 0.f : kNone;
    if (!std::isfinite(scatter) || !std::isfinite(total)) return kNone;
    return scatter >= total ? 1.f : scatter / total;
}

void WalkGuide::count_surface_direction(bool guided) const {
    if (guided) ++stats_.local().surface_guided_samples;
}

void WalkGuide::count_direction(bool guided) const {
    WalkGuideStats& st = stats_.local();
    ++st.direction_samples;
    st.direction_guided += guided;
}

WalkGuideStats WalkGuide::stats() const {
    WalkGuideStats total;
    for (const WalkGuideStats& s : stats_) total += s;
    return total;
}

}  // namespace volguide
