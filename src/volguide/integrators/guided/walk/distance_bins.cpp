#include "volguide/integrators/guided/walk/distance_bins.h"

#include <algorithm>
#include <cmath>

namespace volguide {

std::vector<float> leaf_extents(const SpatialTree& tree) {
    std::vector<float> extent(size_t(tree.leaf_count()));
    for (int i = 0; i < tree.leaf_count(); ++i) {
        const Vec3f e = tree.leaf_bounds(i).extents();
        extent[size_t(i)] = std::cbrt(std::max(0.f, e.x * e.y * e.z));
    }
    return extent;
}

namespace {

// The estimates a constant-proxy walk reads: the field's leaves' tables, or their groups'.
struct LeafTables {
    const LeafEstimates& estimates;
    const std::vector<float>& extent;
    bool lookup(int leaf, const LeafEstimates::Direction& d, float& inscattered, float& L) const {
        return estimates.lookup_average(leaf, d, inscattered, L);
    }
    float extent_of(int leaf) const { return extent[size_t(leaf)]; }
    void prefetch(int leaf, const LeafEstimates::Direction& d) const { estimates.prefetch(leaf, d); }
};
struct GroupTables {
    const LeafGroups& groups;
    bool lookup(int group, const LeafEstimates::Direction& d, float& inscattered, float& L) const {
        return group >= 0 && groups.lookup(group, d, inscattered, L);
    }
    float extent_of(int group) const { return groups.extent(group); }
    void prefetch(int group, const LeafEstimates::Direction& d) const { groups.prefetch(group, d); }
};

// BinSource over a medium of one proxy with sample_incremental_distance's loop: the spans in
// BinSource's order (a leafless stretch before the field, the cursor's leaves, a leafless remainder),
// each span's pieces as BinSource::emit cuts them, each leaf's table prefetched one leaf ahead.
template <class Tables>
class ConstantBins {
  public:
    ConstantBins(const ConstantBinsQuery& q, const Tables& tables, const SpatialTree& tree, int start)
        : q_(q), tables_(tables), cursor_(tree, q.ray, 0.f, q.t_end, start),
          direction_(q.bins.estimates->prepare(q.ray.d)), sigma_max_(q.proxy.sigma_t.max_value()) {}

    DistanceSample sample(Sampler& rng, const GuidedDistanceSettings& settings, BinsReport& report) {
        DistanceSample out;
        IncrementalDistanceWalk walk(settings, choose_distance_strategy(settings, rng.next_1d()));
        out.strategy = walk.strategy();
        Step step{walk, rng, settings, out, report};
        Span cur, ahead;
        bool have = cursor_.next(cur.leaf, cur.t0, cur.t1);
        bool have_ahead = have && pull(ahead);
        while (have) {
            if (cur.t0 > reached_ && span(-1, reached_, cur.t0, step)) return out;
            if (span(cur.leaf, cur.t0, cur.t1, step)) return out;
            cur = ahead;
            have = have_ahead;
            have_ahead = have && pull(ahead);
        }
        if (reached_ < q_.t_end && span(-1, reached_, q_.t_end, step)) return out;
        incremental_surface(walk, settings, out);
        return out;
    }

  private:
    struct Span {
        int leaf = -1;
        float t0 = 0.f, t1 = 0.f;
    };
    struct Step {
        IncrementalDistanceWalk& walk;
        Sampler& rng;
        const GuidedDistanceSettings& settings;
        DistanceSample& out;
        BinsReport& report;
    };
    // The next leaf of the cursor, its table prefetched.
    bool pull(Span& s) {
        if (!cursor_.next(s.leaf, s.t0, s.t1)) return false;
        tables_.prefetch(s.leaf, direction_);
        return true;
    }
    static bool ended(bool ended, int leaf, const Step& s) {
        if (ended) s.report.leaf = leaf;
        return ended;
    }
    // The bins of one span (BinSource::enter, then emit per piece): true when the decision ended there.
    bool span(int leaf, float t0, float t1, const Step& s) {
        reached_ = std::max(reached_, t1);
        if (!(t0 < t1)) return false;  // no proxy segment: no bins
        DistanceBin bin;
        bin.sigma_t = q_.proxy.sigma_t;
        bin.albedo = q_.proxy.albedo;
        bin.inscattered = bin.L = 0.f;
        bin.valid = tables_.lookup(leaf, direction_, bin.inscattered, bin.L);
        bin.confidence = 1.f;
        const bool damping = leaf >= 0 && bin.valid;
        if (damping) bin.confidence = leaf_confidence(tables_.extent_of(leaf), q_.proxy.sigma_t, q_.bins.leaf_tau_max);
        const uint64_t damped = damping && bin.confidence < 1.f ? 1 : 0, invalid = bin.valid ? 0 : 1;
        const float tau = sigma_max_ * (t1 - t0), max_tau = q_.bins.max_tau;
        if (!(tau > max_tau && std::isfinite(tau))) {  // one piece, nearly always
            bin.t0 = t0;
            bin.t1 = t1;
            s.report.damped += damped;
            s.report.invalid += invalid;
            return ended(incremental_step(s.walk, bin, s.rng, s.settings, s.out), leaf, s);
        }
        const int pieces = int(std::min(std::ceil(tau / max_tau), 1e6f));
        const float len = (t1 - t0) / float(pieces);
        for (int piece = 0; piece < pieces;) {
            bin.t0 = t0 + len * float(piece);
            bin.t1 = ++piece == pieces ? t1 : t0 + len * float(piece);
            s.report.damped += damped;
            s.report.invalid += invalid;
            if (ended(incremental_step(s.walk, bin, s.rng, s.settings, s.out), leaf, s)) return true;
        }
        return false;
    }

    const ConstantBinsQuery& q_;
    const Tables& tables_;
    SpatialTree::RayCursor cursor_;
    LeafEstimates::Direction direction_;
    float sigma_max_;
    float reached_ = 0.f;  // the spans entered so far cover (0, reached_)
};

}  // namespace

DistanceSample sample_constant_bins(const ConstantBinsQuery& query, Sampler& rng,
                                    const GuidedDistanceSettings& settings, BinsReport& report) {
    const BinField& bins = query.bins;
    if (bins.groups) {
        const GroupTables tables{*bins.groups};
        return ConstantBins<GroupTables>(query, tables, bins.groups->tree(), -1).sample(rng, settings, report);
    }
    const LeafTables tables{*bins.estimates, bins.leaf_extent};
    return ConstantBins<LeafTables>(query, tables, bins.field.tree(), query.origin_leaf).sample(rng, settings, report);
}

BinSource::BinSource(const Ray& ray, float t_end, const Medium& medium, const BinField& bins,
                     std::vector<ProxySegment>& proxies, int origin_leaf)
    : leaf_extent_(bins.leaf_extent),
      leaf_tau_max_(bins.leaf_tau_max),
      ray_(ray),
      t_end_(t_end),
      medium_(medium),
      estimates_(bins.estimates),
      groups_(bins.estimates ? bins.groups : nullptr),
      proxies_(proxies),
      max_tau_(bins.max_tau),
      cursor_(groups_ ? groups_->tree() : bins.field.tree(), ray, 0.f, t_end, groups_ ? -1 : origin_leaf) {
    proxies_.clear();  // scratch of the previous query: nothing may be read before the first span
    constant_ = medium.constant_proxy(span_proxy_);
    if (estimates_) direction_ = estimates_->prepare(ray.d);
}

bool BinSource::next_span() {
    if (has_pending_) {
        has_pending_ = false;
        enter(pending_.leaf, pending_.t0, pending_.t1);
        return true;
    }
    Span s;
    bool got = false;
    if (has_ahead_) {
        s = ahead_;
        has_ahead_ = false;
        got = true;
    } else {
        got = pull_leaf(s);
    }
    if (got) {
        // One leaf ahead: its table is fetched from memory while this leaf's bins are decided
        // (the lookups of a large field miss the cache, a visible share of a guided render on
        // `thin`; measured: see bench/RESULTS.md (issue 35)).
        if (estimates_ && pull_leaf(ahead_)) {
            has_ahead_ = true;
            if (groups_)
                groups_->prefetch(ahead_.leaf, direction_);
            else
                estimates_->prefetch(ahead_.leaf, direction_);
        }
        if (s.t0 > reached_) {  // the ray enters the field's bounds at s.t0
            pending_ = s;
            has_pending_ = true;
            enter(-1, reached_, s.t0);
        } else {
            enter(s.leaf, s.t0, s.t1);
        }
        return true;
    }
    if (reached_ < t_end_) {
        enter(-1, reached_, t_end_);
        return true;
    }
    return false;
}

bool BinSource::pull_leaf(Span& s) {
    if (cursor_done_) return false;
    if (cursor_.next(s.leaf, s.t0, s.t1)) return true;
    cursor_done_ = true;
    return false;
}

void BinSource::enter(int leaf_index, float t0, float t1) {
    reached_ = std::max(reached_, t1);
    if (constant_) {
        span_proxy_.t0 = t0;
        span_proxy_.t1 = t1;
        proxy_count_ = t0 < t1 ? 1 : 0;
    } else {
        proxies_.clear();
        medium_.proxy_segments(ray_, t0, t1, proxies_);
        proxy_count_ = proxies_.size();
    }
    proxy_ = size_t(-1);
    pieces_ = piece_ = 0;
    inscattered_ = L_ = 0.f;
    leaf_ = leaf_index;
    if (groups_) {
        valid_ = leaf_index >= 0 && groups_->lookup(leaf_index, direction_, inscattered_, L_);
        if (!valid_) inscattered_ = L_ = 0.f;
        return;
    }
    valid_ = estimates_ && estimates_->lookup_average(leaf_index, direction_, inscattered_, L_);
}

}  // namespace volguide
