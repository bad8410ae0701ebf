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
    proxies_.clear();
    medium_.proxy_segments(ray_, t0, t1, proxies_);
    proxy_ = size_t(-1);
    pieces_ = piece_ = 0;
    inscattered_ = L_ = 0.f;
    leaf_ = leaf_index;
    if (groups_) {
        valid_ = leaf_index >= 0 && groups_->lookup(leaf_index, direction_, inscattered_, L_);
        if (!valid_) inscattered_ = L_ = 0.f;
        return;
    }
    Color3 inscattered, incident;
    valid_ = estimates_ && estimates_->lookup(leaf_index, direction_, inscattered, incident);
    if (valid_) {
        inscattered_ = inscattered.average();
        L_ = incident.average();
    }
}

}  // namespace volguide
