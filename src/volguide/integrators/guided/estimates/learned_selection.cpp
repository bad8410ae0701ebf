#include "volguide/integrators/guided/estimates/learned_selection.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <fmt/format.h>
#include <limits>
#include <stdexcept>

namespace volguide {

namespace {

constexpr uint32_t kSelectionMagic = 0x4c534756;  // "VGSL"
// 1, 2: with the retired continuation gate and distance method bytes; 3: without the cost ratio.
constexpr uint32_t kVersion = 4;

size_t nearest_share(float share) {
    size_t best = 0;
    for (size_t k = 1; k < kSelectionShares.size(); ++k)
        if (std::abs(kSelectionShares[k] - share) < std::abs(kSelectionShares[best] - share)) best = k;
    return best;
}

template <class T>
void put(std::string& out, const T& v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    out.append(b, sizeof(T));
}

template <class T>
T get(const std::string& in, size_t& at) {
    if (in.size() - at < sizeof(T) || at > in.size()) throw std::runtime_error("learned selection: truncated");
    T v;
    std::memcpy(&v, in.data() + at, sizeof(T));
    at += sizeof(T);
    return v;
}

constexpr size_t kShares = kSelectionShares.size();

// One cell's second moments for one decision, in double (from exact sums: the same for any
// order of the samples), and the share chosen for it.
struct Entry {
    std::array<double, kShares> m{};
    double current = 0.0;
    double count = 0.0;
    bool learned = false;
    size_t chosen = 0;
};
using Entries = std::vector<std::array<Entry, kDecisionKinds>>;
using PerDecision = std::array<std::array<double, kShares>, kDecisionKinds>;

// The pilot's moments per cell and decision, each at the default share; `pooled`: their sum over
// the cells.
Entries gather_entries(const CellStatistics& stats, const SelectionSettings& settings,
                       const std::array<float, kDecisionKinds>& default_share, PerDecision& pooled) {
    std::array<size_t, kDecisionKinds> default_index{};
    for (int d = 0; d < kDecisionKinds; ++d)
        default_index[size_t(d)] = nearest_share(default_share[size_t(d)]);
    Entries entries(stats.cells());
    pooled = {};
    for (size_t r = 0; r < entries.size(); ++r)
        for (int d = 0; d < kDecisionKinds; ++d) {
            const DecisionMoments& mo = stats.decision(DecisionKind(d), r);
            Entry& e = entries[r][size_t(d)];
            for (size_t k = 0; k < kShares; ++k) e.m[k] = mo.m[k].value();
            e.current = mo.current.value();
            e.count = double(mo.count);
            e.learned = mo.count >= uint64_t(std::max(1, settings.min_samples));
            e.chosen = default_index[size_t(d)];
            for (size_t k = 0; k < kShares; ++k) pooled[size_t(d)][k] += e.m[k];
        }
    return entries;
}

// Shrinkage: a cell's second moments come from few samples of a heavy-tailed quantity, so
// which cells look important is largely which ones happened to catch the rare large
// contributions (at 2 spp, thin's distance decisions were switched off in nearly every cell
// against their cost and relMSE rose, bench/RESULTS.md (issue 35), while the model's prediction for
// all cells together was right). Each cell's mean per decision is pulled towards the mean
// pooled over all cells, with the weight of prior_samples pilot decisions: few samples follow the scene's
// overall verdict, many follow their own.
void shrink_towards_pooled(Entries& entries, const PerDecision& pooled, float prior_samples) {
    const double n0 = std::max(0.f, prior_samples);
    std::array<double, kDecisionKinds> pooled_count{};
    for (const auto& cell : entries)
        for (int d = 0; d < kDecisionKinds; ++d) pooled_count[size_t(d)] += cell[size_t(d)].count;
    for (auto& cell : entries)
        for (int d = 0; d < kDecisionKinds; ++d) {
            Entry& e = cell[size_t(d)];
            if (!(pooled_count[size_t(d)] > 0.0) || !(e.count > 0.0)) continue;
            for (size_t k = 0; k < kShares; ++k) {
                const double prior = pooled[size_t(d)][k] / pooled_count[size_t(d)];
                e.m[k] = e.count * (e.m[k] + n0 * prior) / (e.count + n0);
            }
        }
    for (auto& cell : entries)
        for (Entry& e : cell)
            if (e.learned) e.chosen = size_t(std::min_element(e.m.begin(), e.m.end()) - e.m.begin());
}

// Each learned entry takes argmin_a M_r(a) / V + n_r kappa [a > 0] / T (selection.h); T, the cost in
// decisions, depends on the shares chosen, hence three rounds.
void choose_with_cost(Entries& entries, const CellStatistics& stats, const SelectionSettings& settings) {
    auto cost_of = [&](int d, size_t k, double count) {
        return count * (kSelectionShares[k] > 0.f ? double(settings.kappa[size_t(d)]) : 0.0);
    };
    for (int iteration = 0; iteration < 3; ++iteration) {
        const double V = stats.camera_moment();
        double T = double(stats.unrecorded_decisions());
        for (const auto& cell : entries)
            for (int d = 0; d < kDecisionKinds; ++d) {
                const Entry& e = cell[size_t(d)];
                T += e.count + cost_of(d, e.chosen, e.count);
            }
        if (!(V > 0.0) || !(T > 0.0)) break;
        for (auto& cell : entries)
            for (int d = 0; d < kDecisionKinds; ++d) {
                Entry& e = cell[size_t(d)];
                if (!e.learned) continue;
                double best = std::numeric_limits<double>::infinity();
                for (size_t k = 0; k < kShares; ++k) {
                    const double value = e.m[k] / V + cost_of(d, k, e.count) / T;
                    if (value < best) {
                        best = value;
                        e.chosen = k;
                    }
                }
            }
    }
}

// C_0 / c: a camera sample's decisions over the mean decisions after a continuation point (0: none).
float cost_ratio(const CellStatistics& stats) {
    uint64_t points = 0, after = 0;
    for (int stage = 0; stage < kContinuationStages; ++stage)
        for (size_t cell = 0; cell < stats.cells(); ++cell)
            for (int bin = 0; bin < kContinuationDirectionBins; ++bin) {
                const ContinuationMoments& m = stats.continuation(ContinuationStage(stage), cell, bin);
                points += m.n;
                after += m.cost;
            }
    if (points == 0 || after == 0 || stats.camera_samples() == 0) return 0.f;
    return float((double(stats.cost()) / double(stats.camera_samples())) / (double(after) / double(points)));
}

// Cell r's learned shares.
LearnedSelection::Cell fitted_cell(const std::array<Entry, kDecisionKinds>& entries) {
    LearnedSelection::Cell cell;
    for (int d = 0; d < kDecisionKinds; ++d) {
        const Entry& e = entries[size_t(d)];
        if (e.learned) cell.share[size_t(d)] = kSelectionShares[e.chosen];
    }
    return cell;
}

}  // namespace

LearnedSelection LearnedSelection::fit(const CellStatistics& stats, const SelectionSettings& settings,
                                       const std::array<float, kDecisionKinds>& default_share) {
    PerDecision pooled;  // sum over cells of M(share k)
    Entries entries = gather_entries(stats, settings, default_share, pooled);
    shrink_towards_pooled(entries, pooled, settings.prior_samples);
    choose_with_cost(entries, stats, settings);
    LearnedSelection out;
    out.cells_.resize(entries.size());
    for (size_t r = 0; r < entries.size(); ++r) out.cells_[r] = fitted_cell(entries[r]);
    out.update_learned();
    out.cost_ratio_ = cost_ratio(stats);
    return out;
}

void LearnedSelection::update_learned() {
    learned_ = {};
    for (const Cell& r : cells_)
        for (int d = 0; d < kDecisionKinds; ++d)
            if (r.share[size_t(d)] != kDefault) learned_[size_t(d)] = true;
}

LearnedSelection::Summary LearnedSelection::summary() const {
    Summary s;
    for (const Cell& r : cells_) {
        for (int d = 0; d < kDecisionKinds; ++d) {
            if (r.share[size_t(d)] == kDefault) continue;
            s.mean_share[size_t(d)] += r.share[size_t(d)];
            if (r.share[size_t(d)] > 0.f)
                ++s.guided[size_t(d)];
            else
                ++s.unguided[size_t(d)];
        }
    }
    for (int d = 0; d < kDecisionKinds; ++d) {
        const uint64_t n = s.guided[size_t(d)] + s.unguided[size_t(d)];
        if (n > 0) s.mean_share[size_t(d)] /= double(n);
    }
    return s;
}

std::string LearnedSelection::serialize() const {
    std::string out;
    put(out, kSelectionMagic);
    put(out, kVersion);
    put(out, uint64_t(cells_.size()));
    for (const Cell& r : cells_) {
        for (float s : r.share) put(out, s);
    }
    put(out, cost_ratio_);
    return out;
}

LearnedSelection LearnedSelection::deserialize(const std::string& bytes) {
    size_t at = 0;
    if (get<uint32_t>(bytes, at) != kSelectionMagic) throw std::runtime_error("learned selection: not a selection table");
    const uint32_t version = get<uint32_t>(bytes, at);
    if (version != kVersion)
        throw std::runtime_error(fmt::format("learned selection: version {} (this volguide reads version {}: train again)",
                                             version, kVersion));
    LearnedSelection out;
    const uint64_t n = get<uint64_t>(bytes, at);
    const size_t cell_bytes = kDecisionKinds * sizeof(float);
    if (n > (bytes.size() - at) / cell_bytes) throw std::runtime_error("learned selection: truncated");
    out.cells_.resize(size_t(n));
    for (Cell& r : out.cells_) {
        for (float& s : r.share) {
            s = get<float>(bytes, at);
            if (!(s == kDefault || (s >= 0.f && s <= 1.f)))
                throw std::runtime_error("learned selection: share out of range");
        }
    }
    out.cost_ratio_ = get<float>(bytes, at);
    if (!(out.cost_ratio_ >= 0.f) || !std::isfinite(out.cost_ratio_))
        throw std::runtime_error("learned selection: cost ratio out of range");
    if (at != bytes.size()) throw std::runtime_error("learned selection: trailing bytes");
    out.update_learned();
    return out;
}

}  // namespace volguide
