#include "volguide/guiding/selection.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace volguide {

namespace {

constexpr double kFixedScale = 4294967296.0;  // 2^32
constexpr double kMaxTerm = 1e15;
constexpr double kTwo64 = 18446744073709551616.0;
constexpr uint32_t kSelectionMagic = 0x4c534756;  // "VGSL"
constexpr uint32_t kVersion = 2;  // 1: without the distance method byte

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
using Entries = std::vector<std::array<Entry, kSelectionDecisions>>;
using PerDecision = std::array<std::array<double, kShares>, kSelectionDecisions>;

// The pilot's moments per cell and decision, each at the default share; `pooled`: their sum over
// the cells.
Entries gather_entries(const SelectionStatistics& stats, const SelectionSettings& settings,
                       const std::array<float, kSelectionDecisions>& default_share, PerDecision& pooled) {
    std::array<size_t, kSelectionDecisions> default_index{};
    for (int d = 0; d < kSelectionDecisions; ++d)
        default_index[size_t(d)] = nearest_share(default_share[size_t(d)]);
    Entries entries(stats.cells());
    pooled = {};
    for (size_t r = 0; r < entries.size(); ++r)
        for (int d = 0; d < kSelectionDecisions; ++d) {
            const SelectionStatistics::Moments& mo = stats.moments(SelectionDecision(d), r);
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
    std::array<double, kSelectionDecisions> pooled_count{};
    for (const auto& cell : entries)
        for (int d = 0; d < kSelectionDecisions; ++d) pooled_count[size_t(d)] += cell[size_t(d)].count;
    for (auto& cell : entries)
        for (int d = 0; d < kSelectionDecisions; ++d) {
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
void choose_with_cost(Entries& entries, const SelectionStatistics& stats, const SelectionSettings& settings) {
    auto cost_of = [&](int d, size_t k, double count) {
        return count * (kSelectionShares[k] > 0.f ? double(settings.kappa[size_t(d)]) : 0.0);
    };
    for (int iteration = 0; iteration < 3; ++iteration) {
        const double V = stats.camera_moment();
        double T = double(stats.unrecorded_decisions());
        for (const auto& cell : entries)
            for (int d = 0; d < kSelectionDecisions; ++d) {
                const Entry& e = cell[size_t(d)];
                T += e.count + cost_of(d, e.chosen, e.count);
            }
        if (!(V > 0.0) || !(T > 0.0)) break;
        for (auto& cell : entries)
            for (int d = 0; d < kSelectionDecisions; ++d) {
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

// Per-cell methods (selection.h): a cell's moment and cost (ns) per method, and the rounds' figures.
// Entry `cells` is the rest: the sums over the cells with fewer than min_samples decisions in some
// round, which choose one method together (as the shares' shrinkage lets few samples follow the
// scene's verdict; kept at the configured method they would carry its cost into T unexamined).
struct MethodFit {
    std::vector<std::array<double, kDistanceMethods>> M, C;
    std::vector<bool> learned;
    double V = 0.0, other = 0.0;  // camera-sample second moment and cost outside the cells, per round
};

// The cost no cell holds, per round: the surface vertices' segments (a surface decision's
// intersection and NEE ray; a guided surface decision's extra is its cell's).
double outside_cost(const SelectionStatistics& stats, const SelectionCosts& costs, DistanceMethod method) {
    const auto& round = stats.method_round(method);
    return double(costs.segment) * double(round.decisions[size_t(SelectionDecision::Surface)]);
}

MethodFit gather_methods(const SelectionStatistics& stats, const SelectionSettings& settings) {
    const size_t cells = stats.cells();
    MethodFit f;
    f.M.assign(cells + 1, {});
    f.C.assign(cells + 1, {});
    f.learned.assign(cells + 1, true);
    std::array<double, kDistanceMethods> pooled_m{}, pooled_n{};
    for (size_t r = 0; r < cells; ++r)
        for (int k = 0; k < kDistanceMethods; ++k) {
            const auto& mm = stats.method_moments(DistanceMethod(k), r);
            pooled_m[size_t(k)] += mm.m.value();
            pooled_n[size_t(k)] += double(mm.count);
        }
    const double n0 = std::max(0.f, settings.prior_samples);
    for (size_t r = 0; r < cells; ++r)
        for (int k = 0; k < kDistanceMethods; ++k) {
            const auto& mm = stats.method_moments(DistanceMethod(k), r);
            const double n = double(mm.count);
            if (mm.count < uint64_t(std::max(1, settings.min_samples))) f.learned[r] = false;
            // Shrunk towards the pooled mean per decision as the shares' moments are (shrink_towards_pooled).
            const double prior = pooled_n[size_t(k)] > 0.0 ? pooled_m[size_t(k)] / pooled_n[size_t(k)] : 0.0;
            f.M[r][size_t(k)] = n > 0.0 ? n * (mm.m.value() + n0 * prior) / (n + n0) : 0.0;
            f.C[r][size_t(k)] = method_cell_cost(stats, settings.costs, DistanceMethod(k), r);
        }
    for (size_t r = 0; r < cells; ++r)
        if (!f.learned[r])
            for (int k = 0; k < kDistanceMethods; ++k) {
                f.M[cells][size_t(k)] += stats.method_moments(DistanceMethod(k), r).m.value();
                f.C[cells][size_t(k)] += f.C[r][size_t(k)];
            }
    for (int k = 0; k < kDistanceMethods; ++k) {
        f.V += stats.method_round(DistanceMethod(k)).camera_moment.value() / kDistanceMethods;
        f.other += outside_cost(stats, settings.costs, DistanceMethod(k)) / kDistanceMethods;
    }
    return f;
}

// argmin_m M_r(m) / V + C_r(m) / T per learned cell; T (the cost of a round with every cell's
// choice) depends on the choices, so the rule is iterated until no cell changes (at most
// kMethodIterations), starting from volpath's decisions everywhere: guiding has to earn each cell
// against the time it adds (started from the variance-only choice instead, a cell's share of a time
// inflated by every other cell's guiding is small, and a lookup a million decisions dear did not
// switch one cell off). Ties go to the cheaper method, then to volpath, free flight, vsp, the product, the bins.
constexpr int kMethodIterations = 10;

double method_round_cost(const MethodFit& f, const std::vector<uint8_t>& chosen) {
    double T = f.other;
    for (size_t r = 0; r < chosen.size(); ++r)
        if (f.learned[r]) T += f.C[r][chosen[r]];
    return T;
}

uint8_t best_method(const MethodFit& f, size_t r, double T) {
    constexpr std::array<DistanceMethod, kDistanceMethods> order = {DistanceMethod::Volpath, DistanceMethod::FreeFlight,
                                                                  DistanceMethod::Vsp, DistanceMethod::VspProduct,
                                                                  DistanceMethod::Bins};
    size_t best = size_t(order[0]);
    double best_value = f.M[r][best] / f.V + f.C[r][best] / T;
    for (DistanceMethod m : order) {
        const size_t k = size_t(m);
        const double value = f.M[r][k] / f.V + f.C[r][k] / T;
        if (value < best_value || (value == best_value && f.C[r][k] < f.C[r][best])) {
            best_value = value;
            best = k;
        }
    }
    return uint8_t(best);
}

std::vector<uint8_t> choose_methods(const SelectionStatistics& stats, const SelectionSettings& settings) {
    const MethodFit f = gather_methods(stats, settings);
    std::vector<uint8_t> chosen(f.M.size(), uint8_t(DistanceMethod::Volpath));
    const size_t rest = chosen.size() - 1;
    for (int iteration = 0; iteration < kMethodIterations && f.V > 0.0; ++iteration) {
        const double T = method_round_cost(f, chosen);
        if (!(T > 0.0)) break;
        bool changed = false;
        for (size_t r = 0; r < chosen.size(); ++r) {
            if (!f.learned[r]) continue;
            const uint8_t best = best_method(f, r, T);
            changed |= best != chosen[r];
            chosen[r] = best;
        }
        if (!changed) break;
    }
    for (size_t r = 0; r < rest; ++r)
        if (!f.learned[r]) chosen[r] = chosen[rest];
    chosen.pop_back();
    return chosen;
}

// Cell r's learned shares, and guided RR/splitting switched off at the stages where its estimate
// and the measured radiance disagree by more than rrs_ratio.
LearnedSelection::Cell fitted_cell(const std::array<Entry, kSelectionDecisions>& entries,
                                       const SelectionStatistics& stats, size_t r,
                                       const SelectionSettings& settings) {
    LearnedSelection::Cell cell;
    for (int d = 0; d < kSelectionDecisions; ++d) {
        const Entry& e = entries[size_t(d)];
        if (e.learned) cell.share[size_t(d)] = kSelectionShares[e.chosen];
    }
    const double ratio = double(settings.rrs_ratio);
    for (int s = 0; s < kSelectionStages && ratio >= 1.0; ++s) {
        const SelectionStatistics::Calibration& c = stats.calibration(s, r);
        if (c.count < uint64_t(std::max(1, settings.min_samples))) continue;
        const double est = c.estimate.value(), meas = c.measured.value();
        const bool agrees = est > 0.0 && meas >= est / ratio && meas <= est * ratio;
        cell.rrs[size_t(s)] = agrees ? 1 : 0;
    }
    return cell;
}

}  // namespace

void ExactSum::add_words(uint64_t hi, uint64_t lo) {
    lo_ += lo;
    hi_ += hi + (lo_ < lo ? 1 : 0);
}

void ExactSum::add(double term) {
    if (!(term > 0.0)) return;  // zero, negative rounding noise, NaN
    const double t = std::floor(std::min(term, kMaxTerm) * kFixedScale);  // < 2^82
    const double hi = std::floor(t / kTwo64);
    add_words(uint64_t(hi), uint64_t(t - hi * kTwo64));  // both parts exact in double
}

ExactSum& ExactSum::operator+=(const ExactSum& o) {
    add_words(o.hi_, o.lo_);
    return *this;
}

double ExactSum::value() const {
    return (double(hi_) * kTwo64 + double(lo_)) / kFixedScale;
}

SelectionStatistics::SelectionStatistics(size_t cells) : moments_(cells), calibration_(cells), methods_(cells) {}

void SelectionStatistics::add_method_decision(DistanceMethod method, size_t cell, double s2, uint64_t lookups) {
    if (cell >= methods_.size() || !std::isfinite(s2)) return;
    MethodMoments& m = methods_[cell][size_t(method)];
    ++m.count;
    ++m.events[size_t(CostEvent::Segment)];
    ++m.events[size_t(CostEvent::DistanceDecision)];
    m.events[size_t(CostEvent::BinLookup)] += lookups;
    m.m.add(s2);
}

void SelectionStatistics::add_method_event(DistanceMethod method, size_t cell, CostEvent event, uint64_t n) {
    if (cell >= methods_.size()) return;
    methods_[cell][size_t(method)].events[size_t(event)] += n;
}

void SelectionStatistics::add_method_split_cost(DistanceMethod method, size_t cell, double ns) {
    if (cell >= methods_.size() || !std::isfinite(ns)) return;
    MethodMoments& m = methods_[cell][size_t(method)];
    if (ns > 0.0)
        m.split_ns.add(ns);
    else
        m.roulette_ns.add(-ns);
}

void SelectionStatistics::add_method_camera_sample(DistanceMethod method, double s2,
                                                   const std::array<uint64_t, kSelectionDecisions>& decisions) {
    MethodRound& r = rounds_[size_t(method)];
    ++r.camera_samples;
    for (int d = 0; d < kSelectionDecisions; ++d) r.decisions[size_t(d)] += decisions[size_t(d)];
    if (std::isfinite(s2)) r.camera_moment.add(s2);
}

double method_cell_cost(const SelectionStatistics& stats, const SelectionCosts& costs, DistanceMethod method,
                        size_t cell) {
    const auto& e = stats.method_moments(method, cell).events;
    auto n = [&](CostEvent ev) { return double(e[size_t(ev)]); };
    double c = n(CostEvent::Segment) * double(costs.segment) +
               n(CostEvent::DistanceDecision) * double(costs.decision[size_t(method)]) +
               n(CostEvent::GuidedDirection) * double(costs.guided_direction) +
               n(CostEvent::GuidedSurface) * double(costs.guided_surface);
    // The bins' decision is a walk over lookups; vsp's and the product's constants include theirs.
    if (method == DistanceMethod::Bins) c += n(CostEvent::BinLookup) * double(costs.bin_lookup);
    // Guided RR/splitting reads the estimate at every continuation point of a guided cell (the
    // pilot walks without it: its reads are counted, its extra branches are not).
    if (method != DistanceMethod::Volpath) c += n(CostEvent::Continuation) * double(costs.estimate);
    // Guided RR/splitting's copies and kills (selection_pilot.h); the cell's cost stays >= 0.
    const auto& mm = stats.method_moments(method, cell);
    return std::max(0.0, c + mm.split_ns.value() - mm.roulette_ns.value());
}

double method_round_cost_per_sample(const SelectionStatistics& stats, const SelectionCosts& costs,
                                    DistanceMethod method) {
    const auto& round = stats.method_round(method);
    if (round.camera_samples == 0) return 0.0;
    double c = outside_cost(stats, costs, method);
    for (size_t r = 0; r < stats.cells(); ++r) c += method_cell_cost(stats, costs, method, r);
    return c / double(round.camera_samples);
}

void SelectionStatistics::add_decision(SelectionDecision d, size_t cell, double s2, float q_cur, float p_u,
                                       float p_g) {
    if (cell >= moments_.size() || !(q_cur > 0.f) || !std::isfinite(s2)) return;
    Moments& m = moments_[cell][size_t(d)];
    ++m.count;
    if (!(s2 > 0.0)) return;
    m.current.add(s2);
    for (size_t k = 0; k < kSelectionShares.size(); ++k) {
        const double a = kSelectionShares[k];
        const double q = (1.0 - a) * double(p_u) + a * double(p_g);
        // A share whose mixture cannot sample what was sampled: infinite second moment (clamped).
        m.m[k].add(q > 0.0 ? s2 * double(q_cur) / q : kMaxTerm);
    }
}

void SelectionStatistics::add_camera_sample(double s2) {
    ++camera_samples_;
    if (std::isfinite(s2)) camera_moment_.add(s2);
}

void SelectionStatistics::add_continuation(int stage, size_t cell, double estimate, double measured) {
    if (cell >= calibration_.size() || stage < 0 || stage >= kSelectionStages) return;
    if (!std::isfinite(estimate) || !std::isfinite(measured)) return;
    Calibration& c = calibration_[cell][size_t(stage)];
    ++c.count;
    c.estimate.add(estimate);
    c.measured.add(measured);
}

SelectionStatistics& SelectionStatistics::operator+=(const SelectionStatistics& o) {
    if (moments_.empty()) {
        moments_.resize(o.moments_.size());
        calibration_.resize(o.calibration_.size());
        methods_.resize(o.methods_.size());
    }
    if (o.moments_.size() != moments_.size())
        throw std::logic_error("SelectionStatistics: different cell counts");
    for (size_t r = 0; r < moments_.size(); ++r) {
        for (int d = 0; d < kSelectionDecisions; ++d) {
            Moments& a = moments_[r][size_t(d)];
            const Moments& b = o.moments_[r][size_t(d)];
            for (size_t k = 0; k < kSelectionShares.size(); ++k) a.m[k] += b.m[k];
            a.current += b.current;
            a.count += b.count;
        }
        for (int s = 0; s < kSelectionStages; ++s) {
            Calibration& a = calibration_[r][size_t(s)];
            const Calibration& b = o.calibration_[r][size_t(s)];
            a.estimate += b.estimate;
            a.measured += b.measured;
            a.count += b.count;
        }
    }
    for (size_t r = 0; r < methods_.size(); ++r)
        for (int k = 0; k < kDistanceMethods; ++k) {
            MethodMoments& a = methods_[r][size_t(k)];
            const MethodMoments& b = o.methods_[r][size_t(k)];
            a.m += b.m;
            a.count += b.count;
            for (int e = 0; e < kCostEvents; ++e) a.events[size_t(e)] += b.events[size_t(e)];
            a.split_ns += b.split_ns;
            a.roulette_ns += b.roulette_ns;
        }
    for (int k = 0; k < kDistanceMethods; ++k) {
        rounds_[size_t(k)].camera_moment += o.rounds_[size_t(k)].camera_moment;
        rounds_[size_t(k)].camera_samples += o.rounds_[size_t(k)].camera_samples;
        for (int d = 0; d < kSelectionDecisions; ++d)
            rounds_[size_t(k)].decisions[size_t(d)] += o.rounds_[size_t(k)].decisions[size_t(d)];
    }
    unrecorded_ += o.unrecorded_;
    camera_samples_ += o.camera_samples_;
    camera_moment_ += o.camera_moment_;
    return *this;
}

LearnedSelection LearnedSelection::fit(const SelectionStatistics& stats, const SelectionSettings& settings,
                                       const std::array<float, kSelectionDecisions>& default_share) {
    PerDecision pooled;  // sum over cells of M(share k)
    Entries entries = gather_entries(stats, settings, default_share, pooled);
    shrink_towards_pooled(entries, pooled, settings.prior_samples);
    choose_with_cost(entries, stats, settings);
    LearnedSelection out;
    out.cells_.resize(entries.size());
    for (size_t r = 0; r < entries.size(); ++r)
        out.cells_[r] = fitted_cell(entries[r], stats, r, settings);
    if (settings.choose_distance_method) {
        // The method replaces the distance share: free flight is share 0, the guided methods keep
        // the configured mixture (the rounds measured them with it); volpath: every share 0 and
        // guided RR/splitting off, as in its round.
        const std::vector<uint8_t> methods = choose_methods(stats, settings);
        for (size_t r = 0; r < entries.size(); ++r) {
            Cell& c = out.cells_[r];
            c.distance_method = methods[r];
            if (methods[r] == uint8_t(DistanceMethod::Volpath)) {
                c = volpath_cell();
                continue;
            }
            c.share[size_t(SelectionDecision::Distance)] =
                methods[r] == uint8_t(DistanceMethod::FreeFlight) ? 0.f : kDefault;
        }
    }
    out.update_learned();
    return out;
}

LearnedSelection LearnedSelection::forced_method(size_t cells, DistanceMethod method) {
    LearnedSelection out;
    out.cells_.resize(cells);
    for (Cell& c : out.cells_) c = method == DistanceMethod::Volpath ? volpath_cell() : Cell{};
    for (Cell& c : out.cells_) c.distance_method = uint8_t(method);
    out.update_learned();
    return out;
}

LearnedSelection::Cell LearnedSelection::volpath_cell() {
    Cell c;
    c.share = {0.f, 0.f, 0.f};
    c.rrs = {0, 0};
    c.distance_method = uint8_t(DistanceMethod::Volpath);
    return c;
}

void LearnedSelection::update_learned() {
    learned_ = {};
    has_volpath_ = false;
    for (const Cell& r : cells_) has_volpath_ |= r.distance_method == uint8_t(DistanceMethod::Volpath);
    for (const Cell& r : cells_)
        for (int d = 0; d < kSelectionDecisions; ++d)
            if (r.share[size_t(d)] != kDefault) learned_[size_t(d)] = true;
    for (const Cell& r : cells_)
        if (r.distance_method != kMethodDefault) learned_[size_t(SelectionDecision::Distance)] = true;
}

LearnedSelection::Summary LearnedSelection::summary() const {
    Summary s;
    for (const Cell& r : cells_) {
        for (int d = 0; d < kSelectionDecisions; ++d) {
            if (r.share[size_t(d)] == kDefault) continue;
            s.mean_share[size_t(d)] += r.share[size_t(d)];
            if (r.share[size_t(d)] > 0.f)
                ++s.guided[size_t(d)];
            else
                ++s.unguided[size_t(d)];
        }
        if (!r.rrs[0] || !r.rrs[1]) ++s.rrs_off;
        if (r.distance_method < kDistanceMethods) ++s.methods[r.distance_method];
    }
    for (int d = 0; d < kSelectionDecisions; ++d) {
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
        for (uint8_t b : r.rrs) put(out, b);
        put(out, r.distance_method);
    }
    return out;
}

LearnedSelection LearnedSelection::deserialize(const std::string& bytes) {
    size_t at = 0;
    if (get<uint32_t>(bytes, at) != kSelectionMagic) throw std::runtime_error("learned selection: not a selection table");
    const uint32_t version = get<uint32_t>(bytes, at);
    if (version != kVersion && version != 1) throw std::runtime_error("learned selection: unknown version");
    const uint64_t n = get<uint64_t>(bytes, at);
    const size_t cell_bytes = kSelectionDecisions * sizeof(float) + kSelectionStages + (version >= 2 ? 1 : 0);
    if (n > (bytes.size() - at) / cell_bytes) throw std::runtime_error("learned selection: truncated");
    LearnedSelection out;
    out.cells_.resize(size_t(n));
    for (Cell& r : out.cells_) {
        for (float& s : r.share) {
            s = get<float>(bytes, at);
            if (!(s == kDefault || (s >= 0.f && s <= 1.f)))
                throw std::runtime_error("learned selection: share out of range");
        }
        for (uint8_t& b : r.rrs) {
            b = get<uint8_t>(bytes, at);
            if (b > 1) throw std::runtime_error("learned selection: bad flag");
        }
        if (version >= 2) {
            r.distance_method = get<uint8_t>(bytes, at);
            if (r.distance_method >= kDistanceMethods && r.distance_method != kMethodDefault)
                throw std::runtime_error("learned selection: bad distance method");
        }
    }
    if (at != bytes.size()) throw std::runtime_error("learned selection: trailing bytes");
    out.update_learned();
    return out;
}

}  // namespace volguide
