#include "volguide/integrators/guided/walk/prepared_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "volguide/integrators/guided/walk/distance_bins.h"
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

Color3 PhaseField::inscattered(int leaf, const Vec3f& d) const {
    // The distance decisions' tables when they exist (one bilinear lookup instead of K x J lobes).
    if (estimates) {
        Color3 Li(0.f), L(0.f);
        estimates->lookup(leaf, d, Li, L);
        return Li;
    }
    return inscatter ? inscatter->inscattered(leaf, d) : Color3(0.f);
}

Color3 PhaseField::incident(int leaf, const Vec3f& w) const {
    if (estimates) {  // L~ looking ahead along w
        Color3 Li(0.f), L(0.f);
        estimates->lookup(leaf, w, Li, L);
        return L;
    }
    return GuidingField::incident(field->leaves()[size_t(leaf)], w);
}

float PhaseField::scatter_probability(int leaf, const Vec3f& w, float albedo, float unguided) const {
    constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
    if (leaf < 0) return kNone;
    Color3 Li(0.f), L(0.f);
    if (estimates) {
        if (!estimates->lookup(leaf, w, Li, L)) return kNone;
    } else {
        Li = inscattered(leaf, w);
        L = incident(leaf, w);
    }
    const float scatter = albedo * unguided * Li.average(), total = L.average();
    if (!(scatter > 0.f)) return scatter == 0.f && total > 0.f ? 0.f : kNone;
    if (!std::isfinite(scatter) || !std::isfinite(total)) return kNone;
    return scatter >= total ? 1.f : scatter / total;
}

PreparedField::PreparedField(const Scene& scene, const GuidingField& field, const PreparedFieldSettings& settings)
    : field_(field) {
    direction_lobes_ = direction_lobe_store(field);
    leaf_extent_ = volguide::leaf_extents(field.tree());  // before the groups, which read it
    auto add = [&](const Medium* m) {
        if (!m) return;
        const float g = m->phase().mean_cosine();
        const auto [it, fresh] = phases_.try_emplace(g);
        if (!fresh) return;
        Prepared& p = it->second;
        p.inscatter = InscatterCache(field, hg_phase_vmm(g));
        p.lobes = prepare_phase_lobes(hg_phase_vmm(g));
        if (settings.distance_tables) p.estimates.emplace(field, p.inscatter, settings.estimate_table);
        if (p.estimates && settings.distance_merge > 0.f && settings.estimate_table > 0)
            p.groups.emplace(field.tree(), *p.estimates, leaf_extent_, settings.distance_merge);
    };
    add(scene.sensor().medium());
    for (const auto& shape : scene.shapes()) {
        add(shape->interior_medium());
        add(shape->exterior_medium());
    }
}

PhaseField PreparedField::phase(const PhaseFunction& phase) const {
    PhaseField f;
    f.field = &field_;
    f.leaf_extent = &leaf_extent_;
    const auto it = phases_.find(phase.mean_cosine());
    if (it == phases_.end()) return f;
    const Prepared& p = it->second;
    f.inscatter = &p.inscatter;
    f.estimates = p.estimates ? &*p.estimates : nullptr;
    f.groups = p.groups ? &*p.groups : nullptr;
    f.lobes = &p.lobes;
    return f;
}

std::vector<std::pair<std::string, double>> PreparedField::memory_named() const {
    const double leaves = double(std::max<size_t>(field_.leaves().size(), 1));
    size_t tables = 0;
    for (const auto& [g, p] : phases_) tables += p.estimates ? p.estimates->memory_bytes() : 0;
    const SpatialTree& tree = field_.tree();
    const size_t tree_bytes = size_t(tree.node_count()) * sizeof(SpatialTree::Node) +
                              size_t(tree.leaf_count()) * (sizeof(BBox3f) + 6 * sizeof(uint32_t));
    return {{"memory_direction_lobes_bytes_per_leaf", double(direction_lobes_.bytes()) / leaves},
            {"memory_estimate_tables_bytes_per_leaf", double(tables) / leaves},
            {"memory_tree_bytes_per_leaf", double(tree_bytes) / leaves},
            {"memory_field_leaf_bytes", double(sizeof(GuidingLeaf))}};
}

const Vmm* PreparedField::direction_vmm(int leaf) const {
    const GuidingLeaf& l = field_.leaves()[size_t(leaf)];
    return l.valid_indirect && l.vmm_indirect.count > 0 ? &l.vmm_indirect : nullptr;
}

size_t PreparedField::leaf_group_count() const {
    size_t n = 0;
    for (const auto& [g, p] : phases_) n += p.groups ? size_t(p.groups->group_count()) : 0;
    return n;
}

int PreparedField::leaf_at(const Point3f& x, int hint, uint64_t& descents) const {
    if (field_.empty()) return -1;
    if (hint >= 0 && field_.tree().holds_point(hint, x)) return hint;
    if (!field_.tree().bounds().contains(x)) return -1;
    ++descents;
    return field_.tree().leaf_at(x);
}

}  // namespace volguide
