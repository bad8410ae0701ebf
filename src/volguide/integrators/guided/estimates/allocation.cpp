#include "volguide/integrators/guided/estimates/allocation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "volguide/core/bytes.h"

namespace volguide {

// The fit's parts (a named namespace: the unity build joins anonymous ones across files).
namespace allocation_fit {

constexpr uint32_t kAllocationMagic = 0x414c4756;  // "VGLA"
constexpr uint32_t kAllocationVersion = 1;
constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
constexpr int kFitRounds = 4;

bool known(double x) { return !std::isnan(x); }
double ratio(double a, double b) { return b > 0.0 ? a / b : kUnknown; }

// x from `own` samples shrunk toward the parent's p with `prior` samples of weight; an unknown side
// leaves the other.
double shrink(double x, double own, double p, double prior) {
    if (!known(x) || !(own > 0.0)) return p;
    if (!known(p)) return x;
    return (own * x + prior * p) / (own + prior);
}

// What a region (a cell, or a kd node: the sum over its cells) says of one sampling decision, per
// decision: m(a) = m0 rho(a) the second moment of what follows it under share a, c(a) its cost.
struct DecisionEstimate {
    double n = 0.0, nm = 0.0;  // decisions, of them drawn from a known mixture
    double m0 = kUnknown;
    std::array<double, kShares> rho, alpha;  // M(a) / M(0), after(a) / after(0) over the mixture decisions
    double after0 = kUnknown, own_guided = kUnknown, own_unguided = kUnknown;
    double measured_m = 0.0, measured_c = 0.0;  // as sampled
    DecisionEstimate() {
        rho.fill(kUnknown);
        alpha.fill(kUnknown);
    }
    bool choosable(size_t k) const { return k == 0 || (known(rho[k]) && known(alpha[k]) && known(own_guided)); }
    double m(size_t k) const { return (known(m0) ? m0 : 0.0) * (k == 0 ? 1.0 : rho[k]); }
    double c(size_t k) const {
        const double after = known(after0) ? after0 : 0.0;
        if (k == 0) return (known(own_unguided) ? own_unguided : 0.0) + after;
        return own_guided + after * alpha[k];
    }
};

DecisionEstimate local_estimate(const DecisionMoments& mo) {
    DecisionEstimate e;
    e.nm = double(mo.count);
    e.n = e.nm + double(mo.unguided);
    if (!(e.n > 0.0)) return e;
    const double m_zero = mo.m[0].value(), after_zero = mo.after[0].value();
    e.m0 = (m_zero + mo.unguided_m.value()) / e.n;
    e.after0 = (after_zero + mo.unguided_after.value()) / e.n;
    e.own_unguided = (mo.own_unguided.value() + mo.unguided_own.value()) / e.n;
    e.measured_m = (mo.current.value() + mo.unguided_m.value()) / e.n;
    e.measured_c = (mo.own.value() + mo.current_after.value() + mo.unguided_own.value() + mo.unguided_after.value()) / e.n;
    if (e.nm > 0.0) {
        e.own_guided = mo.own.value() / e.nm;
        for (size_t k = 0; k < kShares; ++k) {
            e.rho[k] = ratio(mo.m[k].value(), m_zero);
            e.alpha[k] = ratio(mo.after[k].value(), after_zero);
        }
    }
    return e;
}

DecisionEstimate shrunk(const DecisionEstimate& local, const DecisionEstimate& parent, double prior) {
    DecisionEstimate e = local;
    e.m0 = shrink(local.m0, local.n, parent.m0, prior);
    e.after0 = shrink(local.after0, local.n, parent.after0, prior);
    e.own_unguided = shrink(local.own_unguided, local.n, parent.own_unguided, prior);
    e.own_guided = shrink(local.own_guided, local.nm, parent.own_guided, prior);
    for (size_t k = 0; k < kShares; ++k) {
        e.rho[k] = shrink(local.rho[k], local.nm, parent.rho[k], prior);
        e.alpha[k] = shrink(local.alpha[k], local.nm, parent.alpha[k], prior);
    }
    return e;
}

// The same for the continuation points of a region, per point and rule.
struct ContinuationEstimate {
    double points = 0.0, known_points = 0.0;
    double m_u = kUnknown, c_u = kUnknown;
    std::array<double, kContinuationRules> rho, alpha;
    double measured_m = 0.0, measured_c = 0.0;
    ContinuationEstimate() {
        rho.fill(kUnknown);
        alpha.fill(kUnknown);
    }
    bool choosable(int r) const { return r == 0 || (known(rho[size_t(r)]) && known(alpha[size_t(r)])); }
    double m(int r) const { return (known(m_u) ? m_u : 0.0) * (r == 0 ? 1.0 : rho[size_t(r)]); }
    double c(int r) const { return (known(c_u) ? c_u : 0.0) * (r == 0 ? 1.0 : alpha[size_t(r)]); }
};

ContinuationEstimate local_estimate(const ContinuationChoiceMoments& mo) {
    ContinuationEstimate e;
    e.known_points = mo.known_points.value();
    e.points = e.known_points + mo.other_points.value();
    if (!(e.points > 0.0)) return e;
    e.m_u = (mo.known_m[0].value() + mo.other_m.value()) / e.points;
    e.c_u = (mo.known_c[0].value() + mo.other_c.value()) / e.points;
    e.measured_m = mo.current_m.value() / e.points;
    e.measured_c = mo.current_c.value() / e.points;
    if (e.known_points > 0.0)
        for (int r = 0; r < kContinuationRules; ++r) {
            e.rho[size_t(r)] = ratio(mo.known_m[size_t(r)].value(), mo.known_m[0].value());
            e.alpha[size_t(r)] = ratio(mo.known_c[size_t(r)].value(), mo.known_c[0].value());
        }
    return e;
}

ContinuationEstimate shrunk(const ContinuationEstimate& local, const ContinuationEstimate& parent, double prior) {
    ContinuationEstimate e = local;
    e.m_u = shrink(local.m_u, local.points, parent.m_u, prior);
    e.c_u = shrink(local.c_u, local.points, parent.c_u, prior);
    for (int r = 0; r < kContinuationRules; ++r) {
        e.rho[size_t(r)] = shrink(local.rho[size_t(r)], local.known_points, parent.rho[size_t(r)], prior);
        e.alpha[size_t(r)] = shrink(local.alpha[size_t(r)], local.known_points, parent.alpha[size_t(r)], prior);
    }
    return e;
}

// Every region's sums (kd nodes bottom-up) and every cell's shrunk estimates (top-down).
struct RegionSums {
    std::array<DecisionMoments, kDecisionKinds> decisions;
    ContinuationChoiceMoments continuation;
    RegionSums& operator+=(const RegionSums& o) {
        for (int d = 0; d < kDecisionKinds; ++d) decisions[size_t(d)] += o.decisions[size_t(d)];
        continuation += o.continuation;
        return *this;
    }
};
struct CellEstimate {
    std::array<DecisionEstimate, kDecisionKinds> decisions;
    ContinuationEstimate continuation;
};

RegionSums cell_sums(const CellStatistics& stats, size_t cell) {
    RegionSums s;
    for (int d = 0; d < kDecisionKinds; ++d) s.decisions[size_t(d)] = stats.decision(DecisionKind(d), cell);
    s.continuation = stats.continuation_choice(cell);
    return s;
}

CellEstimate estimate_of(const RegionSums& sums, const CellEstimate& parent, double prior) {
    CellEstimate e;
    for (int d = 0; d < kDecisionKinds; ++d)
        e.decisions[size_t(d)] = shrunk(local_estimate(sums.decisions[size_t(d)]), parent.decisions[size_t(d)], prior);
    e.continuation = shrunk(local_estimate(sums.continuation), parent.continuation, prior);
    return e;
}

class RegionTree {
  public:
    RegionTree(const CellStatistics& stats, const SpatialTree& tree, double prior)
        : stats_(stats), nodes_(tree.nodes()), prior_(prior), sums_(nodes_.size()), cells_(stats.cells()) {}

    std::vector<CellEstimate> estimates() {
        const CellEstimate none;
        if (nodes_.empty()) {
            for (size_t c = 0; c < cells_.size(); ++c) cells_[c] = estimate_of(cell_sums(stats_, c), none, prior_);
            return cells_;
        }
        sum_below(0);
        const CellEstimate root = estimate_of(sums_[0], none, prior_);
        descend(0, root);
        // The cell outside the field: its parent is the whole field.
        const size_t outside = stats_.cells() - 1;
        cells_[outside] = estimate_of(cell_sums(stats_, outside), root, prior_);
        return cells_;
    }

  private:
    void sum_below(uint32_t node) {
        const SpatialTree::Node& n = nodes_[node];
        if (n.is_leaf()) {
            if (size_t(n.child) < stats_.cells()) sums_[node] = cell_sums(stats_, n.child);
            return;
        }
        sum_below(n.child);
        sum_below(n.child + 1);
        sums_[node] = sums_[n.child];
        sums_[node] += sums_[n.child + 1];
    }
    void descend(uint32_t node, const CellEstimate& e) {
        const SpatialTree::Node& n = nodes_[node];
        if (n.is_leaf()) {
            if (size_t(n.child) < cells_.size()) cells_[n.child] = e;
            return;
        }
        for (uint32_t child : {n.child, n.child + 1}) descend(child, estimate_of(sums_[child], e, prior_));
    }
    const CellStatistics& stats_;
    const std::vector<SpatialTree::Node>& nodes_;
    double prior_;
    std::vector<RegionSums> sums_;
    std::vector<CellEstimate> cells_;
};

// The cells' choices: a share index per sampling decision, a rule for the continuation.
struct CellChoice {
    std::array<size_t, kDecisionKinds> share{};
    int rule = 0;
};

// V and T per camera sample of the choices, from the measured ones and each cell's change.
struct Totals {
    double V = 0.0, T = 0.0;
};
Totals totals_of(const std::vector<CellEstimate>& est, const std::vector<CellChoice>& choice, const Totals& measured,
                 double samples) {
    Totals t = measured;
    for (size_t r = 0; r < est.size(); ++r) {
        for (int d = 0; d < kDecisionKinds; ++d) {
            const DecisionEstimate& e = est[r].decisions[size_t(d)];
            const size_t k = choice[r].share[size_t(d)];
            t.V += e.n / samples * (e.m(k) - e.measured_m);
            t.T += e.n / samples * (e.c(k) - e.measured_c);
        }
        const ContinuationEstimate& c = est[r].continuation;
        t.V += c.points / samples * (c.m(choice[r].rule) - c.measured_m);
        t.T += c.points / samples * (c.c(choice[r].rule) - c.measured_c);
    }
    // The changes are first-order (a decision's change also changes what its parents' moments hold):
    // keep the totals from collapsing.
    t.V = std::max(t.V, 0.05 * measured.V);
    t.T = std::max(t.T, 0.05 * measured.T);
    return t;
}

void choose(const std::vector<CellEstimate>& est, const Totals& t, std::vector<CellChoice>& choice) {
    for (size_t r = 0; r < est.size(); ++r) {
        for (int d = 0; d < kDecisionKinds; ++d) {
            const DecisionEstimate& e = est[r].decisions[size_t(d)];
            double best = std::numeric_limits<double>::infinity();
            for (size_t k = 0; k < kShares; ++k) {
                if (!e.choosable(k)) continue;
                const double value = e.m(k) / t.V + e.c(k) / t.T;
                if (value < best) {
                    best = value;
                    choice[r].share[size_t(d)] = k;
                }
            }
        }
        const ContinuationEstimate& c = est[r].continuation;
        double best = std::numeric_limits<double>::infinity();
        for (int rule = 0; rule < kContinuationRules; ++rule) {
            if (!c.choosable(rule)) continue;
            const double value = c.m(rule) / t.V + c.c(rule) / t.T;
            if (value < best) {
                best = value;
                choice[r].rule = rule;
            }
        }
    }
}

float exploration(double seen, const AllocationSettings& s) {
    if (!(seen > 0.0)) return 1.f;
    return std::clamp(float(s.explore_target / seen), s.explore_min, 1.f);
}

}  // namespace allocation_fit

using namespace allocation_fit;

Allocation Allocation::exploring(size_t cells) {
    Allocation a;
    a.cells_.resize(cells);  // every share kConfigured, every exploration 1
    return a;
}

Allocation Allocation::unguided(size_t cells) {
    Allocation a;
    Cell off;
    off.share.fill(0.f);
    off.explore.fill(0.f);
    off.rule = ContinuationRule::Unguided;
    a.cells_.assign(cells, off);
    return a;
}

Allocation Allocation::fit(const CellStatistics& stats, const SpatialTree& tree, const AllocationSettings& settings) {
    Allocation out = exploring(stats.cells());
    out.cost_ratio_ = float(stats.continuation_cost_ratio());
    const double S = double(stats.camera_samples());
    if (!(S > 0.0) || !(stats.camera_moment() > 0.0) || !(stats.cost() > 0.0)) return out;
    const std::vector<CellEstimate> est = RegionTree(stats, tree, settings.prior).estimates();
    // A typical camera sample: recorded with probability recorded_fraction (the recorded ones measured
    // here paid for it every time).
    const double recording = stats.recording_cost() / S, policy = stats.policy_cost() / S;
    const double moment = stats.camera_moment() / S, floor = 1e-4 * moment;
    const Totals measured{std::max(moment - settings.mean_square, floor),
                          stats.cost() / S - (1.0 - settings.recorded_fraction) * recording};
    std::vector<CellChoice> choice(est.size());
    Totals off = totals_of(est, choice, measured, S);
    Totals t = off;
    for (int round = 0; round < kFitRounds; ++round) {
        choose(est, t, choice);
        t = totals_of(est, choice, measured, S);
    }
    // Everything unguided is the unguided walk: no policy, nothing recorded.
    off.T = std::max(off.T - policy - settings.recorded_fraction * recording, 0.05 * measured.T);
    out.summary_.predicted_gain = (off.V * off.T) / (t.V * t.T);
    out.summary_.predicted_moment_ratio = off.V / t.V;
    out.summary_.predicted_cost_ratio = t.T / off.T;
    // The gain the training's decisions read: with enough control samples (the unguided walk itself,
    // measured), theirs against the samples' as drawn; the first-order prediction above compounds
    // every decision's change over a path and is far too hopeful on long dense paths (bench/RESULTS.md).
    out.gain_ = out.summary_.predicted_gain;
    if (stats.control_samples() >= settings.min_control_samples && stats.control_cost() > 0.0) {
        const double C = double(stats.control_samples());
        const double control_variance = std::max(stats.control_moment() / C - settings.mean_square, floor);
        out.gain_ = control_variance * (stats.control_cost() / C) / (measured.V * measured.T);
        out.summary_.measured = true;
    }
    double decisions[kDecisionKinds + 1] = {};
    for (size_t r = 0; r < est.size(); ++r) {
        Cell& cell = out.cells_[r];
        for (int d = 0; d < kDecisionKinds; ++d) {
            const DecisionEstimate& e = est[r].decisions[size_t(d)];
            const size_t k = choice[r].share[size_t(d)];
            cell.share[size_t(d)] = kSelectionShares[k];
            const double seen = double(stats.decision(DecisionKind(d), r).count + stats.decision(DecisionKind(d), r).unguided);
            cell.explore[size_t(d)] = k > 0 ? 0.f : exploration(seen, settings);
            decisions[d] += e.n;
            if (k > 0) out.summary_.guided[size_t(d)] += e.n;
            else out.summary_.exploring[size_t(d)] += e.n * double(cell.explore[size_t(d)]);
        }
        const ContinuationEstimate& c = est[r].continuation;
        cell.rule = ContinuationRule(choice[r].rule);
        const ContinuationChoiceMoments& cm = stats.continuation_choice(r);
        cell.explore[kDecisionKinds] =
            cell.rule != ContinuationRule::Unguided ? 0.f : exploration(cm.known_points.value() + cm.other_points.value(), settings);
        decisions[kDecisionKinds] += c.points;
        if (cell.rule != ContinuationRule::Unguided) out.summary_.guided[kDecisionKinds] += c.points;
        else out.summary_.exploring[kDecisionKinds] += c.points * double(cell.explore[kDecisionKinds]);
    }
    for (int d = 0; d <= kDecisionKinds; ++d)
        if (decisions[d] > 0.0) {
            out.summary_.guided[size_t(d)] /= decisions[d];
            out.summary_.exploring[size_t(d)] /= decisions[d];
        }
    return out;
}

float Allocation::share(DecisionKind d, size_t cell, float coin, bool learning) const {
    if (cell >= cells_.size()) return kConfigured;
    const Cell& c = cells_[cell];
    if (learning && coin < c.explore[size_t(d)]) return kConfigured;
    return c.share[size_t(d)];
}

ContinuationRule Allocation::rule(size_t cell, float coin, bool learning) const {
    if (cell >= cells_.size()) return ContinuationRule::Splitting;
    const Cell& c = cells_[cell];
    if (learning && coin < c.explore[kDecisionKinds]) return ContinuationRule::Splitting;
    return c.rule;
}

bool Allocation::off() const {
    if (cells_.empty()) return false;
    for (const Cell& c : cells_) {
        if (c.rule != ContinuationRule::Unguided) return false;
        for (int d = 0; d < kDecisionKinds; ++d)
            if (c.share[size_t(d)] != 0.f) return false;
    }
    return true;
}

std::vector<std::pair<std::string, double>> Allocation::named() const {
    static constexpr const char* kKinds[] = {"distance", "direction", "surface", "continuation"};
    std::vector<std::pair<std::string, double>> out{{"allocation_gain", gain_},
                                                    {"allocation_gain_measured", summary_.measured ? 1.0 : 0.0},
                                                    {"allocation_predicted_gain", summary_.predicted_gain},
                                                    {"allocation_predicted_moment_ratio", summary_.predicted_moment_ratio},
                                                    {"allocation_predicted_cost_ratio", summary_.predicted_cost_ratio}};
    for (int d = 0; d <= kDecisionKinds; ++d) {
        out.emplace_back(fmt::format("allocation_{}_guided_fraction", kKinds[d]), summary_.guided[size_t(d)]);
        out.emplace_back(fmt::format("allocation_{}_exploring_fraction", kKinds[d]), summary_.exploring[size_t(d)]);
    }
    return out;
}

std::string Allocation::serialize() const {
    ByteWriter w;
    w.u32(kAllocationMagic);
    w.u32(kAllocationVersion);
    w.u64(cells_.size());
    for (const Cell& c : cells_) {
        for (float s : c.share) w.f32(s);
        for (float e : c.explore) w.f32(e);
        w.u32(uint32_t(c.rule));
    }
    w.f64(gain_);
    w.f32(cost_ratio_);
    for (int d = 0; d <= kDecisionKinds; ++d) {
        w.f64(summary_.guided[size_t(d)]);
        w.f64(summary_.exploring[size_t(d)]);
    }
    return w.take();
}

Allocation Allocation::deserialize(const std::string& bytes) {
    ByteReader r(bytes, "allocation");
    if (r.u32("the magic") != kAllocationMagic) r.fail("not", "an allocation");
    const uint32_t version = r.u32("the version");
    if (version != kAllocationVersion)
        throw std::runtime_error(
            fmt::format("allocation: version {} (this volguide reads version {}: train again)", version, kAllocationVersion));
    const uint64_t n = r.u64("the cell count");
    constexpr size_t kCellBytes = (2 * kDecisionKinds + 1) * 4 + 4;
    if (n > r.left() / kCellBytes) r.fail("truncated in", "the cells");
    Allocation a;
    a.cells_.resize(size_t(n));
    for (Cell& c : a.cells_) {
        for (float& s : c.share) {
            s = r.f32("a share");
            if (!(s == kConfigured || (s >= 0.f && s <= 1.f))) r.fail("a share out of range in", "a cell");
        }
        for (float& e : c.explore) {
            e = r.f32("an exploration");
            if (!(e >= 0.f && e <= 1.f)) r.fail("an exploration probability out of range in", "a cell");
        }
        const uint32_t rule = r.u32("a rule");
        if (rule >= uint32_t(kContinuationRules)) r.fail("an unknown continuation rule in", "a cell");
        c.rule = ContinuationRule(rule);
    }
    a.gain_ = r.f64("the gain");
    if (!std::isfinite(a.gain_) || !(a.gain_ >= 0.0)) r.fail("a gain out of range in", "the record");
    a.cost_ratio_ = r.f32("the cost ratio");
    if (!std::isfinite(a.cost_ratio_) || !(a.cost_ratio_ >= 0.f)) r.fail("a cost ratio out of range in", "the record");
    for (int d = 0; d <= kDecisionKinds; ++d) {
        a.summary_.guided[size_t(d)] = r.f64("the summary");
        a.summary_.exploring[size_t(d)] = r.f64("the summary");
    }
    r.finish();
    return a;
}

}  // namespace volguide
