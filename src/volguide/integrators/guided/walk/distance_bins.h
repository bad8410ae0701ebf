#pragma once
// The bins of a ray segment for the guided distance samplers (guiding/guided_distance.h, docs/theory.md
// §7.6, §7.9): along (0, t_end) of a ray in one medium, the kd-tree leaves the ray crosses (a
// stretch before the field's bounds is a leafless span), cut at the medium's proxy segments
// (majorant cells of a heterogeneous medium) and split so that no bin is optically thicker than
// `max_tau`. Each bin carries its proxy coefficients and its leaf's L~_i and L~ looking along the
// ray (channel averages, §7.8), and its leaf's confidence (trust.h's leaf_confidence) at the bin's
// proxy extinction. With `groups` (leaf_groups.h, built on the same estimates) the bins are the groups
// the ray crosses instead of the leaves.
//
// A source pulls the bins lazily (the incremental sampler stops at the collision): field values,
// the expensive part, are read once per leaf, on entering it. Usage:
//   const std::vector<float> extents = leaf_extents(field.tree());
//   BinSource source(ray, t_end, medium, BinField{field, estimates, nullptr, extents, max_tau, 0.f}, proxies);
//   DistanceBin bin;
//   while (source(bin)) bins.push_back(bin);  // or sample_incremental_distance(source, ...)
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "volguide/core/ray.h"
#include "volguide/core/sampler.h"
#include "volguide/guiding/leaf_groups.h"
#include "volguide/guiding/guided_distance.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/leaf_estimates.h"
#include "volguide/guiding/spatial_tree.h"
#include "volguide/integrators/guided/walk/trust.h"
#include "volguide/media/medium.h"

namespace volguide {

// The cube root of each leaf's volume: the length that sets a leaf's optical size.
std::vector<float> leaf_extents(const SpatialTree& tree);

// What the bins are cut from: the field, its estimates (null: every bin invalid), its leaf groups
// (null: the field's leaves; else built on `estimates`), each leaf's extent (leaf_extents), the
// largest optical depth of a bin and the confidence's tau_max (trust.h).
struct BinField {
    const GuidingField& field;
    const LeafEstimates* estimates;
    const LeafGroups* groups;
    const std::vector<float>& leaf_extent;
    float max_tau;
    float leaf_tau_max;
};

// What a bins decision reports besides its sample: the leaf (with leaf groups: the group) of the bin it
// ended in (-1: outside the field, or it passed every bin) and BinSource's counters.
struct BinsReport {
    int leaf = -1;
    uint64_t invalid = 0, damped = 0;
};

// The incremental sampler (guiding/guided_distance.h) over the bins of (0, t_end) of `ray` in a medium
// of one proxy (Medium::constant_proxy: every bin's coefficients are `proxy`'s) with tabulated
// estimates (bins.estimates of resolution > 0): BinSource's bins with sample_incremental_distance fused
// into one walk over the leaves — a leaf step, a table read and the bin's probabilities per bin, no
// proxy segments per leaf. The same bins, probabilities and random numbers as the two apart, so the
// same sample bit for bit (tests/unit/test_guided_distance.cpp).
struct ConstantBinsQuery {
    const Ray& ray;
    float t_end;
    const ProxySegment& proxy;
    const BinField& bins;
    int origin_leaf = -1;  // as BinSource's
};
DistanceSample sample_constant_bins(const ConstantBinsQuery& query, Sampler& rng,
                                    const GuidedDistanceSettings& settings, BinsReport& report);

class BinSource {
  public:
    // The ray, medium, what `bins` refers to and `proxies` (caller-owned scratch, cleared here) must
    // outlive the source. `origin_leaf`: the field leaf of the vertex the ray leaves from (-1: not
    // known), where the walk starts without a descent.
    BinSource(const Ray& ray, float t_end, const Medium& medium, const BinField& bins,
              std::vector<ProxySegment>& proxies, int origin_leaf = -1);

    // The next bin; false after the last one (at t_end).
    bool operator()(DistanceBin& bin) {
        while (true) {
            if (piece_ < pieces_) {
                emit(bin);
                return true;
            }
            if (++proxy_ < proxy_count_) {
                const ProxySegment& p = proxy();
                const float tau = p.sigma_t.max_value() * (p.t1 - p.t0);
                pieces_ =
                    tau > max_tau_ && std::isfinite(tau) ? int(std::min(std::ceil(tau / max_tau_), 1e6f)) : 1;
                piece_ = 0;
                continue;
            }
            if (!next_span()) return false;
        }
    }
    uint64_t invalid() const { return invalid_; }  // bins without a valid leaf so far
    uint64_t damped() const { return damped_; }    // bins with confidence < 1 (leaf_tau_max)
    // The kd leaf (with leaf groups: the group) of the bin returned last (-1 outside the field).
    int leaf() const { return leaf_; }

  private:
    struct Span {
        int leaf;
        float t0, t1;
    };
    // The current proxy segment: the medium's one proxy over the span, or the span's proxy_segments.
    const ProxySegment& proxy() const { return constant_ ? span_proxy_ : proxies_[proxy_]; }
    // The next piece of the current proxy segment.
    void emit(DistanceBin& bin) {
        const ProxySegment& p = proxy();
        const float len = (p.t1 - p.t0) / float(pieces_);
        bin.t0 = p.t0 + len * float(piece_);
        bin.t1 = ++piece_ == pieces_ ? p.t1 : p.t0 + len * float(piece_);
        bin.sigma_t = p.sigma_t;
        bin.albedo = p.albedo;
        bin.inscattered = inscattered_;
        bin.L = L_;
        bin.valid = valid_;
        bin.confidence = 1.f;
        if (leaf_ >= 0 && valid_) {
            const float extent = groups_ ? groups_->extent(leaf_) : leaf_extent_[size_t(leaf_)];
            bin.confidence = leaf_confidence(extent, p.sigma_t, leaf_tau_max_);
            damped_ += bin.confidence < 1.f ? 1 : 0;
        }
        invalid_ += valid_ ? 0 : 1;
    }
    // Enters the next stretch of (0, t_end): leafless before the field, the cursor's leaves, and a
    // leafless remainder should float round-off leave the cursor short of t_end.
    bool next_span();
    bool pull_leaf(Span& s);
    void enter(int leaf_index, float t0, float t1);

    const std::vector<float>& leaf_extent_;
    float leaf_tau_max_;
    const Ray& ray_;
    float t_end_;
    const Medium& medium_;
    const LeafEstimates* estimates_;
    const LeafGroups* groups_;
    std::vector<ProxySegment>& proxies_;
    // A medium of one proxy (Medium::constant_proxy): span_proxy_ over each span, proxies_ unused.
    bool constant_ = false;
    ProxySegment span_proxy_{0.f, 0.f, Color3(0.f), 0.f};
    size_t proxy_count_ = 0;  // the current span's proxy segments
    float max_tau_;
    SpatialTree::RayCursor cursor_;
    bool cursor_done_ = false, has_pending_ = false;
    Span pending_{-1, 0.f, 0.f};
    Span ahead_{-1, 0.f, 0.f};
    bool has_ahead_ = false;
    LeafEstimates::Direction direction_;  // the ray's place in the leaves' tables
    float reached_ = 0.f;                 // the spans entered so far cover (0, reached_)
    size_t proxy_ = size_t(-1);
    int pieces_ = 0, piece_ = 0;
    bool valid_ = false;
    float inscattered_ = 0.f, L_ = 0.f;
    int leaf_ = -1;
    uint64_t invalid_ = 0, damped_ = 0;
};

}  // namespace volguide
