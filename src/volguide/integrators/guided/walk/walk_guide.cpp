#include "volguide/integrators/guided/walk/walk_guide.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "volguide/integrators/guided/walk/distance_bins.h"
#include "volguide/integrators/guided/walk/distance_sampler.h"
#include "volguide/render/scene.h"
#include "volguide/render/sensor.h"

namespace volguide {

namespace {

// The direction decisions' blocks: each leaf's indirect mixture where it is valid.
LobeStore direction_lobe_store(const GuidingField& field) {
    std::vector<const Vmm*> mixtures;
    std::vector<uint8_t> valid;
    for (const GuidingLeaf& l : field.leaves()) {
        mixtures.push_back(&l.vmm_indirect);
        valid.push_back(l.valid_indirect && l.vmm_indirect.weight_sum() > 0.0);
    }
    return LobeStore(mixtures, valid);
}

}  // namespace

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
    direction_lobes_ = direction_lobe_store(field);
    leaf_extent_ = volguide::leaf_extents(field.tree());  // before the groups, which read it
    auto add = [&](const Medium* m) {
        if (!m) return;
        const float g = m->phase().mean_cosine();
        if (!inscatter_.count(g)) inscatter_.emplace(g, InscatterCache(field, hg_phase_vmm(g)));
        if (!phase_lobes_.count(g)) phase_lobes_.emplace(g, prepare_phase_lobes(hg_phase_vmm(g)));
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
    distance_ = make_distance_sampler(settings_.distance, *this);
    free_flight_ = make_distance_sampler(DistanceGuiding::Standard, *this);
}

WalkGuide::~WalkGuide() = default;

float WalkGuide::confidence(int leaf, const Color3& sigma_t) const {
    if (leaf < 0) return 1.f;
    return leaf_confidence(leaf_extent_[size_t(leaf)], sigma_t, settings_.leaf_tau_max);
}

GuidedShare WalkGuide::guided_share(const TrustPoint& point) const {
    GuidedShare g;
    g.confidence = confidence(point.leaf, point.sigma_t);
    if (point.vertex && g.confidence < kSkipConfidence) {
        g.source = ShareSource::Skipped;
        return g;
    }
    if (point.learned == 0.f) {
        g.source = ShareSource::Unselected;
        return g;
    }
    const bool learned = point.learned != Allocation::kConfigured;
    g.source = learned ? ShareSource::Learned : ShareSource::Configured;
    if (point.kind == DecisionKind::Distance)
        g.undamped = 1.f - (learned ? 1.f - point.learned : settings_.distance_settings.c_T);
    else
        g.undamped = learned ? point.learned : configured_shares()[size_t(point.kind)];
    g.share = g.undamped * g.confidence;
    return g;
}

const LeafEstimates* WalkGuide::estimates_for(const PhaseFunction& phase) const {
    const auto it = estimates_.find(phase.mean_cosine());
    return it == estimates_.end() ? nullptr : &it->second;
}

const LeafGroups* WalkGuide::groups_for(const PhaseFunction& phase) const {
    const auto it = groups_.find(phase.mean_cosine());
    return it == groups_.end() ? nullptr : &it->second;
}

std::vector<std::pair<std::string, double>> WalkGuide::memory_named() const {
    const double leaves = double(std::max<size_t>(field_.leaves().size(), 1));
    size_t tables = 0;
    for (const auto& [g, e] : estimates_) tables += e.memory_bytes();
    const SpatialTree& tree = field_.tree();
    const size_t tree_bytes = size_t(tree.node_count()) * sizeof(SpatialTree::Node) +
                              size_t(tree.leaf_count()) * (sizeof(BBox3f) + 6 * sizeof(uint32_t));
    return {{"memory_direction_lobes_bytes_per_leaf", double(direction_lobes_.bytes()) / leaves},
            {"memory_estimate_tables_bytes_per_leaf", double(tables) / leaves},
            {"memory_tree_bytes_per_leaf", double(tree_bytes) / leaves},
            {"memory_field_leaf_bytes", double(sizeof(GuidingLeaf))}};
}

const PhaseLobes* WalkGuide::phase_lobes(const PhaseFunction& phase) const {
    const auto it = phase_lobes_.find(phase.mean_cosine());
    return it == phase_lobes_.end() ? nullptr : &it->second;
}

const Vmm* WalkGuide::direction_vmm(int leaf) const {
    const GuidingLeaf& l = field_.leaves()[size_t(leaf)];
    return l.valid_indirect && l.vmm_indirect.count > 0 ? &l.vmm_indirect : nullptr;
}

size_t WalkGuide::leaf_group_count() const {
    size_t n = 0;
    for (const auto& [g, r] : groups_) n += size_t(r.group_count());
    return n;
}

int WalkGuide::leaf_at(const Point3f& x, int hint, uint64_t& descents) const {
    if (field_.empty()) return -1;
    if (hint >= 0 && field_.tree().holds_point(hint, x)) return hint;
    if (!field_.tree().bounds().contains(x)) return -1;
    ++descents;
    return field_.tree().leaf_at(x);
}

std::array<float, kDecisionKinds> WalkGuide::configured_shares() const {
    return {1.f - settings_.distance_settings.c_T, 1.f - settings_.phase_prob, 1.f - settings_.bsdf_prob};
}

Color3 WalkGuide::inscattered(int leaf, const PhaseFunction& phase, const Vec3f& d) const {
    // The distance decisions' tables when they exist (one bilinear lookup instead of K x J lobes).
    if (const LeafEstimates* tables = estimates_for(phase)) {
        Color3 Li(0.f), L(0.f);
        tables->lookup(leaf, d, Li, L);
        return Li;
    }
    const auto it = inscatter_.find(phase.mean_cosine());
    return it == inscatter_.end() ? Color3(0.f) : it->second.inscattered(leaf, d);
}

Color3 WalkGuide::incident(int leaf, const PhaseFunction& phase, const Vec3f& w) const {
    if (const LeafEstimates* tables = estimates_for(phase)) {  // L~ looking ahead along w
        Color3 Li(0.f), L(0.f);
        tables->lookup(leaf, w, Li, L);
        return L;
    }
    return GuidingField::incident(field_.leaves()[size_t(leaf)], w);
}

float WalkGuide::scatter_probability(int leaf, const PhaseFunction& phase, const Vec3f& w, float albedo,
                                     float unguided) const {
    constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
    if (leaf < 0) return kNone;
    Color3 Li(0.f), L(0.f);
    if (const LeafEstimates* tables = estimates_for(phase)) {
        if (!tables->lookup(leaf, w, Li, L)) return kNone;
    } else {
        Li = inscattered(leaf, phase, w);
        L = incident(leaf, phase, w);
    }
    const float scatter = albedo * unguided * Li.average(), total = L.average();
    if (!(scatter > 0.f)) return scatter == 0.f && total > 0.f ? 0.f : kNone;
    if (!std::isfinite(scatter) || !std::isfinite(total)) return kNone;
    return scatter >= total ? 1.f : scatter / total;
}

WalkGuideStats WalkGuide::stats() const {
    WalkGuideStats total;
    for (const WalkGuideStats& s : stats_) total += s;
    return total;
}

}  // namespace volguide
