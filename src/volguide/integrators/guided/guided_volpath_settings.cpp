#include "volguide/integrators/guided/guided_volpath_settings.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <span>

namespace volguide {

namespace {

// A choice's name in the scene file and its value.
template <class E>
struct Choice {
    const char* name;
    E value;
};

// How the field is trained: the photon pre-pass (docs/interface.md keeps the parameter's name; its
// other value was retired).
constexpr Choice<bool> kTraining[] = {{"photons", true}};
// The user's names of the distance decisions (one family, walk/distance_sampler.h).
constexpr Choice<DistanceGuiding> kDistance[] = {{"standard", DistanceGuiding::Standard},
                                                 {"incremental", DistanceGuiding::Incremental},
                                                 {"vsp", DistanceGuiding::Vsp}};
constexpr Choice<DirectionGuiding> kDirection[] = {{"phase", DirectionGuiding::Phase},
                                                   {"incident", DirectionGuiding::Incident},
                                                   {"product", DirectionGuiding::Product}};
constexpr Choice<RouletteMode> kRrs[] = {{"standard", RouletteMode::Standard},
                                         {"grr", RouletteMode::Guided},
                                         {"grrs", RouletteMode::GuidedSplitting},
                                         {"ears", RouletteMode::Ears}};
constexpr Choice<FieldEstimate> kEstimate[] = {{"none", FieldEstimate::None},
                                               {"inscattered", FieldEstimate::Inscattered},
                                               {"incident", FieldEstimate::Incident}};

// Parameters of earlier versions that lost at equal time (bench/RESULTS.md) or were test references
// (issue 48): a scene that still names one is told what became of it, at the parameter's line.
struct Retired {
    const char* name;
    const char* why;
};
constexpr const char* kLostTraining =
    "camera-path training and online updates lost to the photon field; the field learns during the render "
    "with refine_passes";
constexpr const char* kFixedRefinement = "the refinement schedule's settings are fixed; refine_passes remains";
constexpr const char* kLostSelection =
    "the learned selection's pilot was replaced by the allocation learned while rendering (issue 59); allocation "
    "remains";
constexpr Retired kRetired[] = {
    {"training_iterations", kLostTraining},
    {"online_spp", kLostTraining},
    {"guide_target", "the variance-aware target lost to the radiance target"},
    {"leaf_contrast", "the light-shaped tree did not improve the render; leaf_samples remains"},
    {"leaf_contrast_samples", "the light-shaped tree did not improve the render; leaf_samples remains"},
    {"refine_spp", kFixedRefinement},
    {"refine_gain", kFixedRefinement},
    {"refine_max_deposits", kFixedRefinement},
    {"max_leaves", kFixedRefinement},
    {"leaf_merge", kFixedRefinement},
    {"distance_denominator", "a test reference; the distance decision uses the volume rendering equation's form"},
    {"estimate_table", "a test reference; the estimates are always tabulated"},
    {"hetero_distance", "a test reference; heterogeneous media use guided tracking"},
    {"direction_radiance", "direction guiding follows the light NEE does not sample"},
    {"vsp_equiangular", "vsp's equiangular share is fixed"},
    {"vsp_camera_buffer", "vsp's camera segments always read the pixel estimate"},
    {"product_candidates", "distance=\"vsp_product\" lost to vsp and the bins"},
    {"pixel_estimate", "the pixel estimate is always the raymarch"},
    {"pixel_estimate_spp", "the pixel estimate is always the raymarch"},
    {"selection_distance_method", kLostSelection},
    {"selection_rrs_ratio", kLostSelection},
    {"selection_cost_distance", "the selection's costs are fixed"},
    {"selection_cost_direction", "the selection's costs are fixed"},
    {"selection_cost_surface", "the selection's costs are fixed"},
    {"selection_cost_lookup", kLostSelection},
    {"ears_record_spp", "rrs=ears records every camera sample"},
    {"selection_spp", kLostSelection},
    {"selection_min_samples", kLostSelection},
    {"method_choice", "the per-tile method choice lost to every tile guided on all nine scenes (issue 55); the "
                      "allocation learns per region and decision while rendering"},
    {"ears_record_fraction", "rrs=ears records every camera sample"},
};

// Values of a parameter that remains (docs/interface.md names them).
struct RetiredValue {
    const char* name;
    const char* value;
    const char* why;
};
constexpr RetiredValue kRetiredValues[] = {
    {"training", "progressive", kLostTraining},
    {"distance", "tabulated", "the full-CDF sampler is a test reference; \"incremental\" samples the same distribution"},
    {"distance", "vsp_product", "it lost to \"vsp\" and \"incremental\" at equal time"},
};

void reject_retired(const Properties& props) {
    for (const Retired& r : kRetired)
        if (props.has(r.name)) props.fail_at(r.name, "guided_volpath: '{}' was retired: {}", r.name, r.why);
    for (const RetiredValue& r : kRetiredValues)
        if (props.has(r.name) && props.get_string(r.name) == r.value)
            props.fail_at(r.name, "guided_volpath: {}=\"{}\" was retired: {}", r.name, r.value, r.why);
    for (const Properties::Entry& e : props.entries())
        if (e.name.rfind("selection_cost_ns_", 0) == 0)
            props.fail_at(e.name, "guided_volpath: '{}' was retired: {}", e.name, kLostSelection);
}

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

// training, photons, max_deposits, photon_focus, training_fraction, and the field's leaf_samples and lobes.
void read_training(const Properties& props, GuidedVolPathSettings& s) {
    read_choice<bool>(props, "training", true, kTraining);
    s.photons = props.get_int("photons", s.photons);
    if (s.photons < 1) props.fail_at("photons", "guided_volpath: photons must be >= 1, got {}", s.photons);
    s.max_deposits = props.get_int("max_deposits", s.max_deposits);
    if (s.max_deposits < 0)
        props.fail_at("max_deposits", "guided_volpath: max_deposits must be >= 0 (0: no cap), got {}",
                      s.max_deposits);
    s.photon_focus = props.get_bool("photon_focus", s.photon_focus);
    s.training_fraction = props.get_float("training_fraction", s.training_fraction);
    if (!(s.training_fraction > 0.f && s.training_fraction < 1.f))
        props.fail_at("training_fraction", "guided_volpath: training_fraction must be in (0, 1), got {}",
                      s.training_fraction);
    const int64_t leaf_samples = props.get_int("leaf_samples", 2000);
    if (leaf_samples < 1)
        props.fail_at("leaf_samples", "guided_volpath: leaf_samples must be >= 1, got {}", leaf_samples);
    s.field.tree.max_samples = int(std::min<int64_t>(leaf_samples, 1 << 30));
    s.field.lobes = int_in(props, "lobes", s.field.lobes, 1, kVmmMaxLobes);
}

// refine_passes (the schedule's and the refinement's other settings are their defaults); an error
// with load_field.
void read_refinement(const Properties& props, GuidedVolPathSettings& s) {
    s.refine.passes = int_in(props, "refine_passes", s.refine.passes, 0, 32, " (0: off)");
    s.refinement.field = s.field;
    if (s.refine.passes > 0 && props.has("load_field"))
        props.fail_at("refine_passes", "guided_volpath: refine_passes cannot refine a loaded field (it keeps the "
                                       "statistics of the photons it was trained from)");
}

// distance and its parameters (c_T, p_max, filter_A, leaf_tau_max, distance_merge).
void read_distance(const Properties& props, const VolPathSettings& walk, WalkGuideSettings& g) {
    g.distance = read_choice<DistanceGuiding>(props, "distance", DistanceGuiding::Incremental, kDistance);
    GuidedDistanceSettings& d = g.distance_settings;
    d.c_T = unit_interval(props, "c_T", d.c_T);
    d.p_max = props.get_float("p_max", d.p_max);
    if (!(d.p_max > 0.f && d.p_max <= 1.f))
        props.fail_at("p_max", "guided_volpath: p_max must be in (0, 1], got {}", d.p_max);
    d.filter_A = unit_interval(props, "filter_A", d.filter_A);
    g.leaf_tau_max = finite_at_least(props, "leaf_tau_max", g.leaf_tau_max, 0.f, " (0: off)");
    g.distance_merge = finite_at_least(props, "distance_merge", g.distance_merge, 0.f, " (0: off)");
    if (g.distance != DistanceGuiding::Standard && walk.equiangular)
        props.fail_at("equiangular", "guided_volpath: equiangular sampling cannot be combined with distance={}",
                      choice_name<DistanceGuiding>(kDistance, g.distance));
}

// direction and its parameters (phase_prob, surface_guiding, bsdf_prob).
void read_direction(const Properties& props, WalkGuideSettings& g) {
    g.direction = read_choice<DirectionGuiding>(props, "direction", DirectionGuiding::Product, kDirection);
    g.phase_prob = unit_interval(props, "phase_prob", g.phase_prob);
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
        props.fail_at("rrs_branch_budget",
                      "guided_volpath: rrs_branch_budget must be 0 (adaptive) or a finite value >= 1, got {}",
                      r.branch_budget);
    if (r.mode == RouletteMode::Ears && props.has("rrs_window"))
        props.fail_at("rrs_window", "guided_volpath: rrs_window does not apply to rrs=ears (no weight window)");
}

// rrs=ears (continuation_snapshot.h): ears_min_samples, ears_budget_factor (errors with another rrs); the
// walk's throughput roulette, ears' fallback, is rr_rule=bounded unless rr_rule is given; the branch
// budget is adaptive unless rrs_branch_budget is given.
void read_ears(const Properties& props, GuidedVolPathSettings& s) {
    // grrs too: where the field has no usable estimate the walk's roulette plays, by the bounded rule
    // (issue 55).
    if (s.roulette.mode == RouletteMode::GuidedSplitting && !props.has("rr_rule"))
        s.walk.rr_rule = RouletteRule::Bounded;
    if (s.roulette.mode != RouletteMode::Ears) {
        for (const char* name : {"ears_min_samples", "ears_budget_factor"})
            if (props.has(name)) props.fail_at(name, "guided_volpath: {} only applies to rrs=ears", name);
        return;
    }
    EarsSettings& e = s.ears;
    e.min_samples = uint64_t(int_in(props, "ears_min_samples", int(e.min_samples), 2, 1 << 30));
    e.budget_factor = finite_at_least(props, "ears_budget_factor", e.budget_factor, 1.f);
    e.fixed_budget = s.roulette.branch_budget;
    e.max_branches = s.roulette.max_branches;
    e.min_budget = std::min(e.min_budget, float(e.max_branches));
    if (!props.has("rr_rule")) s.walk.rr_rule = RouletteRule::Bounded;
}

// Guided RR/splitting's pixel estimate (the allocation's learning uses it too): pixel_estimate_rays,
// pixel_estimate_floor, save_pixel_estimate; the rrs_* parameters are errors with rrs=standard (they
// would silently do nothing), the pixel estimate's unless the allocation is learned.
void read_pixel_estimate(const Properties& props, GuidedVolPathSettings& s) {
    s.pixel.rays_per_pixel = int_in(props, "pixel_estimate_rays", s.pixel.rays_per_pixel, 1, 1024);
    s.pixel.floor_fraction = props.get_float("pixel_estimate_floor", s.pixel.floor_fraction);
    if (!(s.pixel.floor_fraction > 0.f) || std::isinf(s.pixel.floor_fraction))
        props.fail_at("pixel_estimate_floor",
                      "guided_volpath: pixel_estimate_floor must be a finite value > 0, got {}",
                      s.pixel.floor_fraction);
    if (props.has("save_pixel_estimate")) s.save_pixel_estimate = props.get_string("save_pixel_estimate");
    s.pixel.volume_only = s.walk.volume_only;
    s.pixel.hide_emitters = s.walk.hide_emitters;
    if (s.roulette.mode != RouletteMode::Standard) return;
    for (const char* name : {"rrs_window", "rrs_q_min", "rrs_q_max", "rrs_max_branches", "rrs_branch_budget"})
        if (props.has(name))
            props.fail_at(name, "guided_volpath: {} only applies to rrs=grr, grrs or ears (rrs=standard)", name);
    if (s.learn_allocation) return;
    for (const char* name : {"pixel_estimate_rays", "pixel_estimate_floor", "save_pixel_estimate"})
        if (props.has(name))
            props.fail_at(name, "guided_volpath: {} only applies to rrs=grr, grrs or ears or a learned allocation "
                                "(allocation=true)", name);
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
    reject_retired(props);
    s.walk = VolPathSettings::from(props);
    read_training(props, s);
    read_refinement(props, s);
    // The guided decisions: distance, direction, RR and splitting (the paper's full system by default).
    read_distance(props, s.walk, s.guide);
    read_direction(props, s.guide);
    read_roulette(props, s.roulette);
    read_ears(props, s);
    s.learn_allocation = props.get_bool("allocation", s.learn_allocation);
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
        "max_depth={}, rr_depth={}, rr_rule={}, photons={}, refine_passes={}, leaf_samples={}, lobes={}, "
        "distance={}, distance_merge={}, direction={}, surface_guiding={}, rrs={}, rrs_window={}, "
        "rrs_branch_budget={}, allocation={}, equiangular={}, estimate={}",
        walk.max_depth, walk.rr_depth, roulette_rule_name(walk.rr_rule), photons, refine.passes,
        field.tree.max_samples, field.lobes, choice_name<DistanceGuiding>(kDistance, guide.distance),
        guide.distance_merge, choice_name<DirectionGuiding>(kDirection, guide.direction), guide.surface,
        choice_name<RouletteMode>(kRrs, roulette.mode), roulette.window, roulette.branch_budget, learn_allocation,
        walk.equiangular, choice_name<FieldEstimate>(kEstimate, estimate));
}

}  // namespace volguide
