#include "volguide/guiding/field_refinement.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "volguide/core/parallel.h"
#include "volguide/vmm/vmm_split_merge.h"

namespace volguide {

namespace {

double refined_box_volume(const BBox3f& b) {
    const Vec3f e = b.extents();
    return double(e.x) * double(e.y) * double(e.z);
}

bool refine_carries_radiance(const RadianceSample& s) { return s.weight.is_finite() && s.weight.average() > 0.f; }

// The statistics a batch EM would collect from the mixture's own distribution with `n` samples: per
// lobe its weight's share of them and its mean direction scaled by its mean cosine A3(kappa)
// (docs/theory.md §22.2). What a leaf's history becomes when its lobes change.
VmmStatistics mixture_statistics(const Vmm& vmm, double n) {
    VmmStatistics s;
    s.count = vmm.count;
    for (int k = 0; k < vmm.count; ++k) {
        const double w = double(vmm.weight[k]) * n;
        s.weight[size_t(k)] = w;
        s.direction[size_t(k)] = Vec3d(vmm.lobe(k).mu) * (w * vmf_mean_cosine(double(vmm.kappa[k])));
    }
    s.total = n;
    s.sample_count = n;
    return s;
}

// Merges the pair of lobes whose moment-matched merge loses least until at most `lobes` remain.
int merge_to_capacity(Vmm& vmm, int lobes) {
    int merges = 0;
    while (vmm.count > lobes) {
        int best_a = 0, best_b = 1;
        double best = INFINITY;
        for (int a = 0; a < vmm.count; ++a)
            for (int b = a + 1; b < vmm.count; ++b) {
                const double c = merge_cost({vmm.weight[a], vmm.lobe(a)}, {vmm.weight[b], vmm.lobe(b)});
                if (c < best) best = c, best_a = a, best_b = b;
            }
        vmm.merge(best_a, best_b);
        ++merges;
    }
    return merges;
}

}  // namespace

// A leaf's subtree after a pass: nodes[0] is its root; a leaf node's `child` indexes `states`.
struct FieldRefinement::Grown {
    std::vector<SpatialTree::Node> nodes{SpatialTree::Node{}};
    std::vector<LeafState> states;
    RefinementReport report;
};

FieldRefinement::FieldRefinement(const GuidingField& initial, std::span<const RadianceSample> samples,
                                 double photons, const FieldRefinementSettings& settings)
    : settings_(settings), photons_(photons), first_photons_(photons) {
    if (initial.empty()) throw std::invalid_argument("field refinement: an empty initial field");
    if (!(photons > 0)) throw std::invalid_argument("field refinement: the initial pass traced no photons");
    const SpatialTree& tree = initial.tree();
    leaves_.resize(size_t(tree.leaf_count()));
    // The initial mixtures stay as fitted; their statistics are their E-step on the samples.
    FieldRefinementSettings once = settings_;
    once.em_iterations = 0;
    once.lobe_split_merge = false;
    parallel_for(0, tree.leaf_count(), [&](int l) {
        const std::span<const uint32_t> idx = tree.leaf_samples(l);
        const GuidingLeaf& leaf = initial.leaves()[size_t(l)];
        LeafState& st = leaves_[size_t(l)];
        st.all.vmm = leaf.vmm;
        st.all.valid = leaf.valid;
        st.indirect.vmm = leaf.vmm_indirect;
        st.indirect.valid = leaf.valid_indirect;
        RefinementReport unused;
        update_with(once, st, idx, samples, photons, unused);
    });
    tree_ = SpatialTree::from_nodes(tree.bounds(), tree.nodes());
}

VmmFitSettings FieldRefinement::fit_settings(const FieldRefinementSettings& s) {
    VmmFitSettings fit = s.field.fit;
    fit.initial_lobes = s.field.lobes;
    return fit;
}

void FieldRefinement::update(LeafState& state, std::span<const uint32_t> idx, std::span<const RadianceSample> samples,
                             double photons, RefinementReport& report) const {
    update_with(settings_, state, idx, samples, photons, report);
}

// The pass's samples of one leaf into its statistics: flux, sample count, direction moment, and one
// incremental EM fit of each of its two mixtures.
void FieldRefinement::update_with(const FieldRefinementSettings& settings, LeafState& state,
                                  std::span<const uint32_t> idx, std::span<const RadianceSample> samples,
                                  double photons, RefinementReport& report) {
    std::vector<DirectionalSample> dirs, indirect;
    dirs.reserve(idx.size());
    for (uint32_t i : idx) {
        const RadianceSample& s = samples[i];
        if (!s.weight.is_finite()) continue;
        for (int c = 0; c < 3; ++c) state.flux[c] += photons * double(s.weight[c]);
        const float w = s.weight.average();
        if (!(w > 0.f)) continue;
        state.samples += 1;
        state.moment += Vec3d(s.direction) * (photons * double(w));
        state.moment_weight += photons * double(w);
        dirs.push_back({s.direction, w});
        if (s.direct)
            state.any_direct = true;
        else
            indirect.push_back({s.direction, w});
    }
    update_shape(settings, state.all, dirs, report);
    update_shape(settings, state.indirect, indirect, report);
}

void FieldRefinement::update_shape(const FieldRefinementSettings& settings, Shape& shape,
                                   std::span<const DirectionalSample> dirs, RefinementReport& report) {
    if (dirs.empty()) return;
    const VmmFitSettings fit = fit_settings(settings);
    if (!shape.valid) {
        // No mixture yet (the leaf had too few samples): this pass's own fit, once it has enough.
        if (int(dirs.size()) < settings.field.min_samples) return;
        Vmm vmm;
        fit_vmm(vmm, dirs, fit);
        if (vmm.count == 0) return;
        shape.vmm = vmm;
        shape.valid = true;
        shape.stats = VmmStatistics{};
        shape.seen = 0;
    }
    // Incremental EM (Neal and Hinton): the E-step sees this pass's samples, the M-step the statistics
    // of every pass so far (docs/theory.md §22.2).
    VmmStatistics batch, total = shape.stats;
    double previous = 0;
    for (int it = 0; it < std::max(settings.em_iterations, 1); ++it) {
        const double ll = expectation(shape.vmm, dirs, fit, batch);
        total = shape.stats.count == batch.count ? shape.stats : VmmStatistics{};
        total.count = batch.count;
        total.add_scaled(batch, 1.0);
        total.sample_count = shape.seen + batch.total;
        if (settings.em_iterations == 0) break;  // statistics only: the mixture stays as it is
        maximization(shape.vmm, total, fit);
        if (it > 0 && std::abs(ll - previous) <= fit.convergence * std::max({std::abs(previous), batch.total, 1.0}))
            break;
        previous = ll;
    }
    shape.seen += batch.total;
    shape.stats = total;
    if (!settings.lobe_split_merge) return;
    // The split test refits each lobe's samples with two lobes: on an evenly strided subset, so that its
    // cost per pass stays bounded per leaf.
    std::vector<DirectionalSample> few;
    std::span<const DirectionalSample> judged = dirs;
    const size_t cap = size_t(std::max(settings.lobe_split_samples, 16));
    if (dirs.size() > cap) {
        const size_t stride = (dirs.size() + cap - 1) / cap;
        for (size_t i = 0; i < dirs.size(); i += stride) few.push_back(dirs[i]);
        judged = few;
    }
    const int splits = split_lobes(shape.vmm, judged, fit);
    const int merges = merge_redundant_lobes(shape.vmm, fit) + merge_to_capacity(shape.vmm, settings.field.lobes);
    if (splits + merges > 0) shape.stats = mixture_statistics(shape.vmm, shape.seen);
    report.lobe_splits += splits;
    report.lobe_merges += merges;
}

// The samples per leaf past which a leaf splits: leaf_samples x (photons / first photons)^split_growth,
// raised (deterministically, by 1/8 at a time) until the leaves the pass would make fit max_leaves.
double FieldRefinement::split_threshold(std::span<const double> expected) const {
    double threshold = double(settings_.field.tree.max_samples) *
                       std::pow(photons_ / first_photons_, settings_.split_growth);
    for (int round = 0; round < 400; ++round) {
        double leaves = 0;
        for (size_t l = 0; l < expected.size(); ++l)
            leaves += std::max(1.0, std::ceil(expected[l] / (threshold * leaves_[l].split_scale)));
        if (leaves <= double(settings_.max_leaves)) break;
        threshold *= 1.125;
    }
    return threshold;
}

// A copy of `state` for a part of its region holding `count` of its samples' share and `flux` of
// their flux: the statistics in proportion, the mixtures as they are.
FieldRefinement::LeafState FieldRefinement::part(const LeafState& state, double count, double flux) {
    LeafState p = state;
    for (double& f : p.flux) f *= flux;
    p.samples *= count;
    p.moment *= flux;
    p.moment_weight *= flux;
    p.split_scale = 1.f;
    for (Shape* s : {&p.all, &p.indirect}) {
        s->stats.scale(count);
        s->stats.sample_count *= count;
        s->seen *= count;
    }
    return p;
}

// Splits `state` where its new samples lie while it holds more than the threshold and may still make
// `extra` leaves, then adds each part's samples to it (update).
void FieldRefinement::grow_into(Grown& g, uint32_t node, LeafState state, std::vector<uint32_t> idx,
                                const BBox3f& box, int extra, std::span<const RadianceSample> samples,
                                double photons, double threshold) const {
    double counted = 0, weight = 0;
    for (uint32_t i : idx)
        if (refine_carries_radiance(samples[i])) counted += 1, weight += double(samples[i].weight.average());
    if (extra > 0 && counted >= 2 && state.samples + counted > threshold * double(state.split_scale)) {
        // Where its new samples lie: the kd-tree build's rule (spatial_tree.h).
        const auto [axis, split] = mean_split(
            idx, box, [&](uint32_t i) -> const Point3f& { return samples[i].position; },
            [&](uint32_t i) { return refine_carries_radiance(samples[i]); });
        if (axis < 3) {
            std::vector<uint32_t> lower, upper;
            double counted_lower = 0, weight_lower = 0;
            for (uint32_t i : idx) {
                const bool low = samples[i].position[axis] < split;
                (low ? lower : upper).push_back(i);
                if (low && refine_carries_radiance(samples[i]))
                    counted_lower += 1, weight_lower += double(samples[i].weight.average());
            }
            const double share = counted_lower / counted;
            const double flux_share = weight > 0 ? weight_lower / weight : share;
            const int extra_lower = int(std::lround(double(extra - 1) * share));
            const uint32_t child = uint32_t(g.nodes.size());
            g.nodes[node] = SpatialTree::Node{split, child, uint8_t(axis)};
            g.nodes.resize(g.nodes.size() + 2);
            BBox3f lo_box = box, hi_box = box;
            lo_box.hi[axis] = split;
            hi_box.lo[axis] = split;
            g.report.leaf_splits += 1;
            grow_into(g, child, part(state, share, flux_share), std::move(lower), lo_box, extra_lower, samples,
                      photons, threshold);
            grow_into(g, child + 1, part(state, 1 - share, 1 - flux_share), std::move(upper), hi_box,
                      extra - 1 - extra_lower, samples, photons, threshold);
            return;
        }
    }
    update(state, idx, samples, photons, g.report);
    g.nodes[node] = SpatialTree::Node{0.f, uint32_t(g.states.size()), 3};
    g.states.push_back(std::move(state));
}

RefinementReport FieldRefinement::add(std::span<const RadianceSample> samples, double photons) {
    RefinementReport report;
    if (!(photons > 0)) return report;
    photons_ += photons;
    const int L = tree_.leaf_count();
    const BBox3f& bounds = tree_.bounds();
    std::vector<std::vector<uint32_t>> by_leaf(static_cast<size_t>(L));
    std::vector<double> expected(static_cast<size_t>(L), 0.0);
    for (size_t l = 0; l < size_t(L); ++l) expected[l] = leaves_[l].samples;
    for (size_t i = 0; i < samples.size(); ++i) {
        const int l = tree_.leaf_at(min(max(samples[i].position, bounds.lo), bounds.hi));
        if (l < 0) continue;
        by_leaf[size_t(l)].push_back(uint32_t(i));
        expected[size_t(l)] += refine_carries_radiance(samples[i]) ? 1 : 0;
    }
    const double threshold = split_threshold(expected);
    std::vector<Grown> grown(static_cast<size_t>(L));
    parallel_for(0, L, [&](int l) {
        const double t = threshold * double(leaves_[size_t(l)].split_scale);
        const int extra = expected[size_t(l)] > t ? int(std::ceil(expected[size_t(l)] / t)) - 1 : 0;
        grow_into(grown[size_t(l)], 0, leaves_[size_t(l)], std::move(by_leaf[size_t(l)]), tree_.leaf_bounds(l), extra,
                  samples, photons, threshold);
    });
    // The new tree: the old one with every leaf replaced by its grown subtree, in depth-first order.
    std::vector<SpatialTree::Node> nodes;
    std::vector<LeafState> states;
    std::function<void(uint32_t, uint32_t)> copy = [&](uint32_t at, uint32_t old) {
        const SpatialTree::Node& n = tree_.nodes()[old];
        if (!n.is_leaf()) {
            const uint32_t child = uint32_t(nodes.size());
            nodes[at] = SpatialTree::Node{n.split, child, n.axis};
            nodes.resize(nodes.size() + 2);
            copy(child, n.child);
            copy(child + 1, n.child + 1);
            return;
        }
        Grown& g = grown[n.child];
        std::function<void(uint32_t, uint32_t)> splice = [&](uint32_t to, uint32_t from) {
            const SpatialTree::Node& m = g.nodes[from];
            if (m.is_leaf()) {
                nodes[to] = SpatialTree::Node{0.f, uint32_t(states.size()), 3};
                states.push_back(std::move(g.states[m.child]));
                return;
            }
            const uint32_t child = uint32_t(nodes.size());
            nodes[to] = SpatialTree::Node{m.split, child, m.axis};
            nodes.resize(nodes.size() + 2);
            splice(child, m.child);
            splice(child + 1, m.child + 1);
        };
        splice(at, 0);
    };
    nodes.resize(1);
    copy(0, 0);
    for (const Grown& g : grown) {
        report.leaf_splits += g.report.leaf_splits;
        report.lobe_splits += g.report.lobe_splits;
        report.lobe_merges += g.report.lobe_merges;
    }
    rebuild(std::move(nodes), std::move(states));
    merge_smooth_siblings(report);
    report.leaves = tree_.leaf_count();
    report.split_threshold = threshold;
    return report;
}

void FieldRefinement::rebuild(std::vector<SpatialTree::Node> nodes, std::vector<LeafState> states) {
    tree_ = SpatialTree::from_nodes(tree_.bounds(), std::move(nodes));
    leaves_ = std::move(states);
}

// Fluence density and mean direction within the thresholds (FieldRefinementSettings).
bool FieldRefinement::similar(const LeafState& a, const BBox3f& box_a, const LeafState& b, const BBox3f& box_b) const {
    if (a.all.valid != b.all.valid) return false;
    const double da = (a.flux[0] + a.flux[1] + a.flux[2]) / refined_box_volume(box_a);
    const double db = (b.flux[0] + b.flux[1] + b.flux[2]) / refined_box_volume(box_b);
    if (da + db > 0 && std::abs(da - db) > double(settings_.merge_contrast) * (da + db)) return false;
    const Vec3d ma = a.moment_weight > 0 ? a.moment / a.moment_weight : Vec3d(0.0);
    const Vec3d mb = b.moment_weight > 0 ? b.moment / b.moment_weight : Vec3d(0.0);
    return norm(ma - mb) <= double(settings_.merge_direction);
}

// Two leaf siblings whose light agrees (similar) become their parent again, bottom-up: the merged
// leaf sums their statistics and keeps the mixtures of the one with more samples; it waits for twice
// the threshold before it splits again.
void FieldRefinement::merge_smooth_siblings(RefinementReport& report) {
    if (!(settings_.merge_contrast > 0.f)) return;
    const std::vector<SpatialTree::Node>& old = tree_.nodes();
    std::vector<SpatialTree::Node> nodes(1);
    std::vector<LeafState> states;
    // Copies node `from` of the old tree to `to`; returns the new leaf index when it stayed or became a
    // leaf, -1 for an inner node.
    std::function<int(uint32_t, uint32_t, const BBox3f&)> copy = [&](uint32_t to, uint32_t from,
                                                                     const BBox3f& box) -> int {
        const SpatialTree::Node& n = old[from];
        if (n.is_leaf()) {
            nodes[to] = SpatialTree::Node{0.f, uint32_t(states.size()), 3};
            states.push_back(leaves_[n.child]);
            return int(states.size()) - 1;
        }
        const uint32_t child = uint32_t(nodes.size());
        nodes[to] = SpatialTree::Node{n.split, child, n.axis};
        nodes.resize(nodes.size() + 2);
        BBox3f lo = box, hi = box;
        lo.hi[n.axis] = n.split;
        hi.lo[n.axis] = n.split;
        const int a = copy(child, n.child, lo), b = copy(child + 1, n.child + 1, hi);
        if (a < 0 || b < 0 || !similar(states[size_t(a)], lo, states[size_t(b)], hi)) return -1;
        LeafState merged = merge(states[size_t(a)], states[size_t(b)]);
        states.resize(size_t(a));  // a and b are the last two leaves copied
        nodes.resize(child);       // and their nodes the last two
        nodes[to] = SpatialTree::Node{0.f, uint32_t(states.size()), 3};
        states.push_back(std::move(merged));
        report.leaf_merges += 1;
        return int(states.size()) - 1;
    };
    copy(0, 0, tree_.bounds());
    rebuild(std::move(nodes), std::move(states));
}

FieldRefinement::LeafState FieldRefinement::merge(const LeafState& a, const LeafState& b) {
    LeafState m = a.samples >= b.samples ? a : b;
    const LeafState& o = a.samples >= b.samples ? b : a;
    for (int c = 0; c < 3; ++c) m.flux[c] += o.flux[c];
    m.samples += o.samples;
    m.moment += o.moment;
    m.moment_weight += o.moment_weight;
    m.any_direct = a.any_direct || b.any_direct;
    m.split_scale = 2.f * std::max(a.split_scale, b.split_scale);
    for (auto [shape, other] : {std::pair{&m.all, &o.all}, std::pair{&m.indirect, &o.indirect}}) {
        if (!shape->valid) {
            *shape = *other;
            continue;
        }
        shape->seen += other->seen;
        shape->stats = mixture_statistics(shape->vmm, shape->seen);
    }
    return m;
}

GuidingField FieldRefinement::field() const {
    std::vector<GuidingLeaf> leaves(leaves_.size());
    parallel_for(0, int(leaves_.size()), [&](int l) {
        const LeafState& st = leaves_[size_t(l)];
        GuidingLeaf& leaf = leaves[size_t(l)];
        const double norm = photons_ * refined_box_volume(tree_.leaf_bounds(l));
        if (norm > 0)
            leaf.fluence = Color3(float(st.flux[0] / norm), float(st.flux[1] / norm), float(st.flux[2] / norm));
        leaf.samples = uint32_t(std::min(st.samples, 4e9));
        if (st.all.valid) leaf.vmm = st.all.vmm;
        leaf.valid = st.all.valid;
        const Shape& indirect = st.any_direct ? st.indirect : st.all;
        if (indirect.valid) leaf.vmm_indirect = indirect.vmm;
        leaf.valid_indirect = indirect.valid;
    });
    return GuidingField(tree_, std::move(leaves));
}

size_t FieldRefinement::memory_bytes() const {
    return leaves_.capacity() * sizeof(LeafState) + tree_.nodes().capacity() * sizeof(SpatialTree::Node) +
           size_t(tree_.leaf_count()) * (sizeof(BBox3f) + 6 * sizeof(uint32_t));
}

}  // namespace volguide
