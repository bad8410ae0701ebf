#include "volguide/integrators/guided/guided_volpath_settings.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <span>

namespace volguide {

namespace {

// Iteration k traces 2^k spp: 20 iterations are already ~10^6 spp.
constexpr int64_t kMaxTrainingIterations = 20;

// A choice's name in the scene file and its value.
template <class E>
struct Choice {
    const char* name;
    E value;
};

constexpr Choice<TrainingMethod> kTraining[] = {{"photons", TrainingMethod::Photons},
                                                {"progressive", TrainingMethod::Progressive}};
constexpr Choice<DistanceGuiding> kDistance[] = {{"standard", DistanceGuiding::Standard},
                                                 {"incremental", DistanceGuiding::Incremental},
                                                 {"tabulated", DistanceGuiding::Tabulated},
                                                 {"vsp", DistanceGuiding::Vsp},
                                                 {"vsp_product", DistanceGuiding::VspProduct}};
constexpr Choice<DistanceDenominator> kDenominator[] = {{"vre", DistanceDenominator::Vre},
                                                        {"incident", DistanceDenominator::Incident}};
// Heterogeneous media under distance=incremental: guided null-collision tracking (H2) or the bins (H1).
constexpr Choice<bool> kHeteroDistance[] = {{"tracking", true}, {"bins", false}};
constexpr Choice<DirectionGuiding> kDirection[] = {{"phase", DirectionGuiding::Phase},
                                                   {"incident", DirectionGuiding::Incident},
                                                   {"product", DirectionGuiding::Product}};
// direction_radiance: the direction guide learns indirect radiance only (NEE covers the rest) or all.
constexpr Choice<bool> kDirectionRadiance[] = {{"indirect", true}, {"all", false}};
constexpr Choice<RouletteMode> kRrs[] = {{"standard", RouletteMode::Standard},
                                         {"grr", RouletteMode::Guided},
                                         {"grrs", RouletteMode::GuidedSplitting},
                                         {"ears", RouletteMode::Ears}};
constexpr Choice<PixelEstimateMethod> kPixelEstimate[] = {{"raymarch", PixelEstimateMethod::Raymarch},
                                                          {"render", PixelEstimateMethod::Render}};
// guide_target: the field's directional target, E[L] or sqrt(E[L^2]) (docs/theory.md §23).
constexpr Choice<bool> kGuideTarget[] = {{"radiance", false}, {"variance", true}};
constexpr Choice<FieldEstimate> kEstimate[] = {{"none", FieldEstimate::None},
                                               {"inscattered", FieldEstimate::Inscattered},
                                               {"incident", FieldEstimate::Incident}};

template <class E>
const char* choice_name(std::span<const Choice<E>> table, E value) {
    for (const Choice<E>& c : table)
        if (c.value == value) return c.name;
    return "?";  // unreachable: every value a setting can hold is in its table
}

// The value named by parameter `name` (absent: `def`); any other name is an error listing the
// table's names.
template <class E>
E read_choice(const Properties& props, const char* name, E def, std::span<const Choice<E>> table) {
    const std::string value = props.get_string(name, choice_name(table, def));
    for (const Choice<E>& c : table)
        if (value == c.name) return c.value;
    std::string options;
    for (const Choice<E>& c : table) options += (options.empty() ? "" : ", ") + std::string(c.name);
    props.fail_at(name, "guided_volpath: invalid {} '{}' (one of: {})", name, value, options);
}

float unit_interval(const Properties& props, const char* name, float def) {
    const float v = props.get_float(name, def);
    if (!(v >= 0.f && v <= 1.f)) props.fail_at(name, "guided_volpath: {} must be in [0, 1], got {}", name, v);
    return v;
}

int int_in(const Properties& props, const char* name, int64_t def, int64_t lo, int64_t hi, const char* note = "") {
    const int64_t v = props.get_int(name, def);
    if (v < lo || v > hi)
        props.fail_at(name, "guided_volpath: {} must be in [{}, {}]{}, got {}", name, lo, hi, note, v);
    return int(v);
}

float finite_at_least(const Properties& props, const char* name, float def, float lo, const char* note = "") {
    const float v = props.get_float(name, def);
    if (!(v >= lo) || std::isinf(v))
        props.fail_at(name, "guided_volpath: {} must be a finite value >= {}{}, got {}", name, lo, note, v);
    return v;
}

// training, photons, max_deposits, photon_focus, training_iterations, online_spp, guide_target,
// training_fraction, and the field's leaf_samples and lobes.
void read_training(const Properties& props, GuidedVolPathSettings& s) {
    s.training = read_choice<TrainingMethod>(props, "training", s.training, kTraining);
    s.photons = props.get_int("photons", s.photons);
    if (s.photons < 1) props.fail_at("photons", "guided_volpath: photons must be >= 1, got {}", s.photons);
    s.max_deposits = props.get_int("max_deposits", s.max_deposits);
    if (s.max_deposits < 0)
        props.fail_at("max_deposits", "guided_volpath: max_deposits must be >= 0 (0: no cap), got {}",
                      s.max_deposits);
    s.photon_focus = props.get_bool("photon_focus", s.photon_focus);
    s.training_iterations = int_in(props, "training_iterations", s.training_iterations, 1, kMaxTrainingIterations);
    s.online_spp = int_in(props, "online_spp", s.online_spp, 0, 1 << 16, " (0: off)");
    if (s.online_spp > 0 && s.training != TrainingMethod::Progressive)
        props.fail_at("online_spp", "guided_volpath: online_spp needs training=\"progressive\" (the field is rebuilt "
                                    "from the training's samples and the render's)");
    if (s.online_spp > 0 && props.has("load_field"))
        props.fail_at("online_spp", "guided_volpath: online_spp cannot be combined with load_field (a saved field "
                                    "has no training samples to rebuild from)");
    s.field.variance_aware = read_choice<bool>(props, "guide_target", s.field.variance_aware, kGuideTarget);
    if (s.field.variance_aware && s.training != TrainingMethod::Progressive)
        props.fail_at("guide_target", "guided_volpath: guide_target=\"variance\" needs training=\"progressive\" (photons "
                                      "carry no second moment of the camera paths' radiance estimates)");
    // The target shapes the direction decisions' distribution, which direction_radiance=all replaces
    // by the estimates' (walk_guide.h).
    if (s.field.variance_aware && !read_choice<bool>(props, "direction_radiance", true, kDirectionRadiance))
        props.fail_at("guide_target", "guided_volpath: guide_target=\"variance\" needs direction_radiance=\"indirect\" "
                                      "(the direction decisions read the variance-aware distribution only there)");
    s.training_fraction = props.get_float("training_fraction", s.training_fraction);
    if (!(s.training_fraction > 0.f && s.training_fraction < 1.f))
        props.fail_at("training_fraction", "guided_volpath: training_fraction must be in (0, 1), got {}",
                      s.training_fraction);
    const int64_t leaf_samples = props.get_int("leaf_samples", 2000);
    if (leaf_samples < 1)
        props.fail_at("leaf_samples", "guided_volpath: leaf_samples must be >= 1, got {}", leaf_samples);
    s.field.tree.max_samples = int(std::min<int64_t>(leaf_samples, 1 << 30));
    s.field.lobes = int_in(props, "lobes", s.field.lobes, 1, kVmmMaxLobes);
    // The transport-shaped refinement (spatial_tree.h, issue 22).
    s.field.tree.split_contrast = props.get_float("leaf_contrast", s.field.tree.split_contrast);
    if (!(s.field.tree.split_contrast >= 0.f && s.field.tree.split_contrast < 1.f))
        props.fail_at("leaf_contrast", "guided_volpath: leaf_contrast must be in [0, 1) (0: off), got {}",
                      s.field.tree.split_contrast);
    s.field.tree.contrast_min_samples =
        int_in(props, "leaf_contrast_samples", s.field.tree.contrast_min_samples, 1, 1 << 30);
}

// refine_passes, refine_spp, refine_gain, refine_max_deposits, max_leaves, leaf_merge (issue 39); the
// others are errors without refine_passes > 0, refine_passes with anything but a photon field trained here.
void read_refinement(const Properties& props, GuidedVolPathSettings& s) {
    RefinementScheduleSettings& r = s.refine;
    r.passes = int_in(props, "refine_passes", r.passes, 0, 32, " (0: off)");
    r.first_spp = int_in(props, "refine_spp", r.first_spp, 2, 1 << 20);
    r.gain = props.get_float("refine_gain", float(r.gain));
    if (!(r.gain >= 0.0 && r.gain < 1.0))
        props.fail_at("refine_gain", "guided_volpath: refine_gain must be in [0, 1), got {}", r.gain);
    s.refine_max_deposits = props.get_int("refine_max_deposits", s.refine_max_deposits);
    if (s.refine_max_deposits < 1)
        props.fail_at("refine_max_deposits", "guided_volpath: refine_max_deposits must be >= 1, got {}",
                      s.refine_max_deposits);
    FieldRefinementSettings& f = s.refinement;
    f.max_leaves = int_in(props, "max_leaves", f.max_leaves, 1, 1 << 24);
    f.merge_contrast = props.get_float("leaf_merge", f.merge_contrast);
    if (!(f.merge_contrast >= 0.f && f.merge_contrast < 1.f))
        props.fail_at("leaf_merge", "guided_volpath: leaf_merge must be in [0, 1) (0: off), got {}", f.merge_contrast);
    f.merge_direction = f.merge_contrast;
    f.field = s.field;
    if (r.passes == 0) {
        for (const char* name : {"refine_spp", "refine_gain", "refine_max_deposits", "max_leaves", "leaf_merge"})
            if (props.has(name)) props.fail_at(name, "guided_volpath: {} only applies with refine_passes > 0", name);
        return;
    }
    if (s.training != TrainingMethod::Photons)
        props.fail_at("refine_passes", "guided_volpath: refine_passes needs training=\"photons\" (it adds further photon "
                                       "passes to the field)");
    if (props.has("load_field"))
        props.fail_at("refine_passes", "guided_volpath: refine_passes cannot refine a loaded field (it keeps the "
                                       "statistics of the photons it was trained from)");
}

// distance and its parameters (c_T, p_max, filter_A, distance_denominator, leaf_tau_max,
// estimate_table, distance_merge, hetero_distance, vsp_equiangular, vsp_camera_buffer).
void read_distance(const Properties& props, const VolPathSettings& walk, WalkGuideSettings& g) {
    g.distance = read_choice<DistanceGuiding>(props, "distance", DistanceGuiding::Incremental, kDistance);
    GuidedDistanceSettings& d = g.distance_settings;
    d.c_T = unit_interval(props, "c_T", d.c_T);
    d.p_max = props.get_float("p_max", d.p_max);
    if (!(d.p_max > 0.f && d.p_max <= 1.f))
        props.fail_at("p_max", "guided_volpath: p_max must be in (0, 1], got {}", d.p_max);
    d.filter_A = unit_interval(props, "filter_A", d.filter_A);
    d.denominator = read_choice<DistanceDenominator>(props, "distance_denominator", d.denominator, kDenominator);
    g.leaf_tau_max = finite_at_least(props, "leaf_tau_max", g.leaf_tau_max, 0.f, " (0: off)");
    g.estimate_table = int_in(props, "estimate_table", g.estimate_table, 0, 256, " (0: exact)");
    g.distance_merge = finite_at_least(props, "distance_merge", g.distance_merge, 0.f, " (0: off)");
    if (g.distance_merge > 0.f && g.estimate_table == 0)
        props.fail_at("distance_merge", "guided_volpath: distance_merge needs the estimate tables (estimate_table > 0)");
    if (g.distance != DistanceGuiding::Standard && walk.equiangular)
        props.fail_at("equiangular", "guided_volpath: equiangular sampling cannot be combined with distance={}",
                      choice_name<DistanceGuiding>(kDistance, g.distance));
    g.guided_tracking = read_choice<bool>(props, "hetero_distance", g.guided_tracking, kHeteroDistance);
    g.vsp_equiangular = unit_interval(props, "vsp_equiangular", g.vsp_equiangular);
    if (props.has("vsp_equiangular") && g.distance != DistanceGuiding::Vsp)
        props.fail_at("vsp_equiangular", "guided_volpath: vsp_equiangular needs distance=\"vsp\"");
    g.vsp_camera_buffer = props.get_bool("vsp_camera_buffer", g.vsp_camera_buffer);
    if (props.has("vsp_camera_buffer") && g.distance != DistanceGuiding::Vsp && g.distance != DistanceGuiding::VspProduct)
        props.fail_at("vsp_camera_buffer", "guided_volpath: vsp_camera_buffer needs distance=\"vsp\" or \"vsp_product\"");
    g.product_candidates = int_in(props, "product_candidates", g.product_candidates, 1, 64);
}

// direction and its parameters (phase_prob, direction_radiance, surface_guiding, bsdf_prob).
void read_direction(const Properties& props, WalkGuideSettings& g) {
    g.direction = read_choice<DirectionGuiding>(props, "direction", DirectionGuiding::Product, kDirection);
    g.phase_prob = unit_interval(props, "phase_prob", g.phase_prob);
    g.direction_indirect = read_choice<bool>(props, "direction_radiance", g.direction_indirect, kDirectionRadiance);
    g.surface = props.get_bool("surface_guiding", g.surface);
    g.bsdf_prob = unit_interval(props, "bsdf_prob", g.bsdf_prob);
}

// rrs and its parameters (rrs_window, rrs_q_min, rrs_q_max, rrs_max_branches, rrs_branch_budget).
void read_roulette(const Properties& props, RouletteSplittingSettings& r) {
    r.mode = read_choice<RouletteMode>(props, "rrs", RouletteMode::GuidedSplitting, kRrs);
    r.window = finite_at_least(props, "rrs_window", r.window, 1.f);
    r.q_min = props.get_float("rrs_q_min", r.q_min);
    if (!(r.q_min > 0.f && r.q_min <= 1.f))
        props.fail_at("rrs_q_min", "guided_volpath: rrs_q_min must be in (0, 1], got {}", r.q_min);
    r.q_max = finite_at_least(props, "rrs_q_max", r.q_max, 1.f);
    r.max_branches = int_in(props, "rrs_max_branches", r.max_branches, 1, 4096);
    r.branch_budget = props.get_float("rrs_branch_budget", r.branch_budget);
    if (!(r.branch_budget == 0.f || (r.branch_budget >= 1.f && std::isfinite(r.branch_budget))))
        props.fail_at("rrs_branch_budget", "guided_volpath: rrs_branch_budget must be 0 (off) or a finite value >= 1, got {}",
                      r.branch_budget);
    if (r.mode == RouletteMode::Ears && props.has("rrs_window"))
        props.fail_at("rrs_window", "guided_volpath: rrs_window does not apply to rrs=ears (no weight window)");
}

// rrs=ears (continuation_stats.h): ears_min_samples, ears_budget_factor, ears_record_spp,
// ears_record_fraction (errors with another rrs); the
// walk's throughput roulette, ears' fallback, is rr_rule=bounded unless rr_rule is given; the branch
// budget is adaptive unless rrs_branch_budget is given.
void read_ears(const Properties& props, GuidedVolPathSettings& s) {
    if (s.roulette.mode != RouletteMode::Ears) {
        for (const char* name : {"ears_min_samples", "ears_budget_factor", "ears_record_spp", "ears_record_fraction"})
            if (props.has(name)) props.fail_at(name, "guided_volpath: {} only applies to rrs=ears", name);
        return;
    }
    EarsSettings& e = s.ears;
    e.min_samples = uint64_t(int_in(props, "ears_min_samples", int(e.min_samples), 2, 1 << 30));
    e.budget_factor = finite_at_least(props, "ears_budget_factor", e.budget_factor, 1.f);
    e.record_spp = int_in(props, "ears_record_spp", e.record_spp, 0, 1 << 30);
    e.record_fraction = props.get_float("ears_record_fraction", e.record_fraction);
    if (!(e.record_fraction > 0.f && e.record_fraction <= 1.f))
        props.fail_at("ears_record_fraction", "guided_volpath: ears_record_fraction must be in (0, 1], got {}",
                      e.record_fraction);
    e.fixed_budget = s.roulette.branch_budget;
    e.max_branches = s.roulette.max_branches;
    e.min_budget = std::min(e.min_budget, float(e.max_branches));
    if (!props.has("rr_rule")) s.walk.rr_rule = RouletteRule::Bounded;
}

// The method choice's cost model (guiding/selection.h SelectionCosts, ns per event):
// selection_cost_lookup (a lookup of the bins), selection_cost_ns_<event> for the others; only with
// selection_distance_method=true.
void read_method_costs(const Properties& props, SelectionSettings& s) {
    SelectionCosts& c = s.costs;
    const std::array<std::pair<const char*, float*>, 9> costs = {{
        {"selection_cost_lookup", &c.bin_lookup},
        {"selection_cost_ns_segment", &c.segment},
        {"selection_cost_ns_free_flight", &c.decision[size_t(DistanceMethod::FreeFlight)]},
        {"selection_cost_ns_vsp", &c.decision[size_t(DistanceMethod::Vsp)]},
        {"selection_cost_ns_vsp_product", &c.decision[size_t(DistanceMethod::VspProduct)]},
        {"selection_cost_ns_guided_direction", &c.guided_direction},
        {"selection_cost_ns_guided_surface", &c.guided_surface},
        {"selection_cost_ns_estimate", &c.estimate},
        {"selection_cost_ns_volpath_decision", &c.decision[size_t(DistanceMethod::Volpath)]},
    }};
    for (const auto& [name, value] : costs) {
        if (props.has(name) && !s.choose_distance_method)
            props.fail_at(name, "guided_volpath: {} only applies with selection_distance_method=true", name);
        *value = finite_at_least(props, name, *value, 0.f);
    }
    // The bins' decision outside its lookups is free flight's arithmetic (SelectionCosts).
    c.decision[size_t(DistanceMethod::Bins)] = c.decision[size_t(DistanceMethod::FreeFlight)];
}

// Learned selection (guiding/selection.h): selection_spp (0: off), selection_min_samples,
// selection_cost_distance / _direction / _surface (kappa), selection_rrs_ratio.
// selection_distance_method (issue 37: the per-cell choice among free flight, vsp, vsp_product, the
// incremental bins and volpath) with selection_cost_lookup, the cost model's ns per lookup of the bins.
void read_selection(const Properties& props, DistanceGuiding distance, SelectionSettings& s) {
    s.pilot_spp = int_in(props, "selection_spp", s.pilot_spp, 0, 64, " (0: off)");
    s.choose_distance_method = props.get_bool("selection_distance_method", s.choose_distance_method);
    if (s.choose_distance_method && (s.pilot_spp == 0 || distance == DistanceGuiding::Standard))
        props.fail_at("selection_distance_method",
                      "guided_volpath: selection_distance_method needs a learned selection (selection_spp > 0) and a "
                      "guided distance decision (distance != standard)");
    if (props.has("product_candidates") && distance != DistanceGuiding::VspProduct && !s.choose_distance_method)
        props.fail_at("product_candidates",
                      "guided_volpath: product_candidates only applies to distance=vsp_product or "
                      "selection_distance_method=true");
    read_method_costs(props, s);
    s.min_samples = int_in(props, "selection_min_samples", s.min_samples, 1, 1 << 30);
    s.kappa[0] = finite_at_least(props, "selection_cost_distance", s.kappa[0], 0.f);
    s.kappa[1] = finite_at_least(props, "selection_cost_direction", s.kappa[1], 0.f);
    s.kappa[2] = finite_at_least(props, "selection_cost_surface", s.kappa[2], 0.f);
    s.rrs_ratio = finite_at_least(props, "selection_rrs_ratio", s.rrs_ratio, 0.f, " (0: off)");
    if (s.rrs_ratio > 0.f && s.rrs_ratio < 1.f)
        props.fail_at("selection_rrs_ratio", "guided_volpath: selection_rrs_ratio must be 0 (off) or >= 1, got {}",
                      s.rrs_ratio);
    if (s.pilot_spp > 0) return;
    for (const char* name : {"selection_min_samples", "selection_cost_distance", "selection_cost_direction",
                             "selection_cost_surface", "selection_rrs_ratio"})
        if (props.has(name))
            props.fail_at(name, "guided_volpath: {} only applies to a learned selection (selection_spp > 0)", name);
}

// Guided RR/splitting's pixel estimate (learned selection's pilot uses it too): pixel_estimate, pixel_estimate_rays, pixel_estimate_spp,
// pixel_estimate_floor, save_pixel_estimate; all of them, and the rrs_* parameters, are errors
// with rrs=standard (they would silently do nothing).
void read_pixel_estimate(const Properties& props, GuidedVolPathSettings& s) {
    s.pixel_estimate = read_choice<PixelEstimateMethod>(props, "pixel_estimate", s.pixel_estimate, kPixelEstimate);
    s.pixel.rays_per_pixel = int_in(props, "pixel_estimate_rays", s.pixel.rays_per_pixel, 1, 1024);
    s.pixel_estimate_spp = int_in(props, "pixel_estimate_spp", s.pixel_estimate_spp, 1, 4096);
    s.pixel.floor_fraction = props.get_float("pixel_estimate_floor", s.pixel.floor_fraction);
    if (!(s.pixel.floor_fraction > 0.f) || std::isinf(s.pixel.floor_fraction))
        props.fail_at("pixel_estimate_floor",
                      "guided_volpath: pixel_estimate_floor must be a finite value > 0, got {}",
                      s.pixel.floor_fraction);
    if (props.has("save_pixel_estimate")) s.save_pixel_estimate = props.get_string("save_pixel_estimate");
    s.pixel.volume_only = s.walk.volume_only;
    s.pixel.hide_emitters = s.walk.hide_emitters;
    if (s.roulette.mode != RouletteMode::Standard) return;
    for (const char* name : {"rrs_window", "rrs_q_min", "rrs_q_max", "rrs_max_branches", "rrs_branch_budget",
                             "selection_rrs_ratio"})
        if (props.has(name))
            props.fail_at(name, "guided_volpath: {} only applies to rrs=grr or rrs=grrs (rrs=standard)", name);
    if (s.selection.pilot_spp > 0) return;
    for (const char* name : {"pixel_estimate", "pixel_estimate_rays", "pixel_estimate_spp", "pixel_estimate_floor",
                             "save_pixel_estimate"})
        if (props.has(name))
            props.fail_at(name, "guided_volpath: {} only applies to rrs=grr or rrs=grrs or a learned selection "
                                "(selection_spp > 0)", name);
}

// load_field, resolved like Mitsuba's file resolver: a relative path that does not exist here is
// looked up beside the scene file.
std::string resolve_field_path(const Properties& props) {
    std::filesystem::path p(props.get_string("load_field"));
    if (p.is_relative() && !std::filesystem::exists(p)) {
        const auto beside = std::filesystem::path(props.location_of("load_field").file).parent_path() / p;
        if (std::filesystem::exists(beside)) p = beside;
    }
    if (!std::filesystem::exists(p))
        props.fail_at("load_field", "guided_volpath: the guiding field \"{}\" does not exist", p.string());
    return p.string();
}

}  // namespace

GuidedVolPathSettings GuidedVolPathSettings::from(const Properties& props) {
    GuidedVolPathSettings s;
    s.location = props.location();
    s.walk = VolPathSettings::from(props);
    read_training(props, s);
    read_refinement(props, s);
    // The guided decisions: distance, direction, RR and splitting (the paper's full system by default).
    read_distance(props, s.walk, s.guide);
    read_direction(props, s.guide);
    read_roulette(props, s.roulette);
    read_ears(props, s);
    read_selection(props, s.guide.distance, s.selection);
    read_pixel_estimate(props, s);
    s.estimate = read_choice<FieldEstimate>(props, "estimate", s.estimate, kEstimate);
    if (s.estimate != FieldEstimate::None && s.refine.passes > 0)
        props.fail_at("refine_passes", "guided_volpath: refine_passes does not apply to estimate (no render to refine during)");
    if (props.has("save_field")) s.save_field = props.get_string("save_field");
    if (props.has("load_field")) s.load_field = resolve_field_path(props);
    return s;
}

std::string GuidedVolPathSettings::to_string() const {
    return fmt::format(
        "max_depth={}, rr_depth={}, rr_rule={}, training={}, photons={}, training_iterations={}, online_spp={}, guide_target={}, "
        "refine_passes={}, refine_spp={}, refine_gain={}, refine_max_deposits={}, max_leaves={}, leaf_merge={}, "
        "leaf_samples={}, leaf_contrast={}, leaf_contrast_samples={}, "
        "lobes={}, distance={}, distance_merge={}, vsp_equiangular={}, vsp_camera_buffer={}, hetero_distance={}, direction={}, surface_guiding={}, rrs={}, rrs_window={}, "
        "rrs_branch_budget={}, selection_spp={}, selection_distance_method={}, pixel_estimate={}, equiangular={}, estimate={}",
        walk.max_depth, walk.rr_depth, roulette_rule_name(walk.rr_rule), choice_name<TrainingMethod>(kTraining, training), photons,
        training_iterations, online_spp, choice_name<bool>(kGuideTarget, field.variance_aware), refine.passes,
        refine.first_spp, refine.gain, refine_max_deposits,
        refinement.max_leaves, refinement.merge_contrast, field.tree.max_samples, field.tree.split_contrast,
        field.tree.contrast_min_samples, field.lobes,
        choice_name<DistanceGuiding>(kDistance, guide.distance), guide.distance_merge, guide.vsp_equiangular,
        guide.vsp_camera_buffer,
        choice_name<bool>(kHeteroDistance, guide.guided_tracking),
        choice_name<DirectionGuiding>(kDirection, guide.direction), guide.surface,
        choice_name<RouletteMode>(kRrs, roulette.mode), roulette.window, roulette.branch_budget,
        selection.pilot_spp, selection.choose_distance_method, choice_name<PixelEstimateMethod>(kPixelEstimate, pixel_estimate), walk.equiangular,
        choice_name<FieldEstimate>(kEstimate, estimate));
}

}  // namespace volguide
