#include "volguide/render/bsdfs/ior.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <variant>

namespace volguide {

namespace {

struct NamedIor {
    const char* name;
    float value;
};

// Values at ~589 nm, 0-20 degrees C (Hecht, Optics), identical to Mitsuba's table.
constexpr NamedIor kDielectrics[] = {
    {"vacuum", 1.0f},      {"helium", 1.000036f},        {"hydrogen", 1.000132f},
    {"air", 1.000277f},    {"carbon dioxide", 1.00045f}, {"water", 1.3330f},
    {"acetone", 1.36f},    {"ethanol", 1.361f},          {"carbon tetrachloride", 1.461f},
    {"glycerol", 1.4729f}, {"benzene", 1.501f},          {"silicone oil", 1.52045f},
    {"bromine", 1.661f},   {"water ice", 1.31f},         {"fused quartz", 1.458f},
    {"pyrex", 1.470f},     {"acrylic glass", 1.49f},     {"polypropylene", 1.49f},
    {"bk7", 1.5046f},      {"sodium chloride", 1.544f},  {"amber", 1.55f},
    {"pet", 1.5750f},      {"diamond", 2.419f},
};

std::string to_lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

}  // namespace

std::optional<float> named_ior(const std::string& name) {
    const std::string lower = to_lower(name);
    for (const NamedIor& e : kDielectrics)
        if (lower == e.name) return e.value;
    return std::nullopt;
}

float lookup_ior(const Properties& props, const std::string& param, const std::string& default_name) {
    const Properties::Entry* e = props.find(param);
    float value;
    if (e && !std::holds_alternative<std::string>(e->value)) {
        value = props.get_float(param);
    } else {
        const std::string name = props.get_string(param, default_name);
        std::optional<float> v = named_ior(name);
        if (!v) {
            std::string choices;
            for (const NamedIor& n : kDielectrics)
                choices += (choices.empty() ? "" : ", ") + std::string(n.name);
            props.fail_at(param, "unknown index of refraction '{}' for '{}'; valid names: {}", name, param,
                          choices);
        }
        value = *v;
    }
    if (!(std::isfinite(value) && value > 0.f))
        props.fail_at(param, "'{}' must be a finite index of refraction > 0 (got {})", param, value);
    return value;
}

}  // namespace volguide

namespace volguide {

std::optional<ComplexIor> conductor_preset(const std::string& name) {
    if (name == "none") return ComplexIor{Color3(0.f), Color3(1.f)};
    for (const ConductorPreset& p : conductor_table())
        if (name == p.name) return p.ior;
    return std::nullopt;
}

}  // namespace volguide
