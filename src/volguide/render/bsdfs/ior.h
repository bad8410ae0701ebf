#pragma once
// Named indices of refraction, as Mitsuba 3's tables: dielectrics (int_ior / ext_ior) and
// conductor material presets (complex IOR eta + i k, as RGB).
#include <optional>
#include <string>

#include "volguide/core/color.h"
#include "volguide/core/properties.h"

namespace volguide {

// The IOR named `name` (case-insensitive), e.g. "bk7", "water", "air"; nullopt if unknown.
std::optional<float> named_ior(const std::string& name);
// Parameter `param` given as a number or a material name; `default_name` when absent.
// Unknown names, and values that are not finite and > 0, are input errors.
float lookup_ior(const Properties& props, const std::string& param, const std::string& default_name);

struct ComplexIor {
    Color3 eta, k;
};
// Conductor preset by Mitsuba's material name ("Cu", "Au", "Ag", "Al", ...; "none" = perfect
// mirror with eta 0, k 1); nullopt if unknown.
std::optional<ComplexIor> conductor_preset(const std::string& name);

}  // namespace volguide
