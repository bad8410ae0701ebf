#include "volguide/core/properties.h"

namespace volguide {

void Properties::set(std::string name, std::string category, Value value, SourceLocation loc) {
    if (!name.empty() && has(name)) fail(loc, "parameter '{}' is specified twice", name);
    entries_.push_back(Entry{std::move(name), std::move(category), std::move(value), std::move(loc), false});
}

const Properties::Entry* Properties::find(const std::string& name) const {
    for (const auto& e : entries_)
        if (!e.name.empty() && e.name == name) return &e;
    return nullptr;
}

bool Properties::has(const std::string& name) const { return find(name) != nullptr; }

const SourceLocation& Properties::location_of(const std::string& name) const {
    const Entry* e = find(name);
    return e ? e->loc : loc_;
}

void Properties::mark_used(const std::string& name) const {
    if (const Entry* e = find(name)) e->used = true;
}

const Properties::Entry& Properties::require(const std::string& name) const {
    const Entry* e = find(name);
    if (!e) fail(loc_, "{} '{}': missing required parameter '{}'", category_, type_, name);
    e->used = true;
    return *e;
}

void Properties::wrong_type(const Entry& e, const char* expected) const {
    fail(e.loc, "parameter '{}' of {} '{}' must be {} (got <{}>)", e.name, category_, type_, expected, e.category);
}

bool Properties::get_bool(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* v = std::get_if<bool>(&e.value)) return *v;
    wrong_type(e, "a boolean");
}
bool Properties::get_bool(const std::string& name, bool def) const { return has(name) ? get_bool(name) : def; }

int64_t Properties::get_int(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* v = std::get_if<int64_t>(&e.value)) return *v;
    wrong_type(e, "an integer");
}
int64_t Properties::get_int(const std::string& name, int64_t def) const { return has(name) ? get_int(name) : def; }

float Properties::get_float(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* v = std::get_if<double>(&e.value)) return float(*v);
    if (auto* v = std::get_if<int64_t>(&e.value)) return float(*v);
    wrong_type(e, "a float");
}
float Properties::get_float(const std::string& name, float def) const { return has(name) ? get_float(name) : def; }

std::string Properties::get_string(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* v = std::get_if<std::string>(&e.value)) return *v;
    wrong_type(e, "a string");
}
std::string Properties::get_string(const std::string& name, const std::string& def) const {
    return has(name) ? get_string(name) : def;
}

Color3 Properties::get_color(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* v = std::get_if<Color3>(&e.value)) return *v;
    if (auto* v = std::get_if<double>(&e.value)) return Color3(float(*v));
    if (auto* v = std::get_if<int64_t>(&e.value)) return Color3(float(*v));
    wrong_type(e, "a color (rgb, spectrum or float)");
}
Color3 Properties::get_color(const std::string& name, const Color3& def) const {
    return has(name) ? get_color(name) : def;
}

Vec3f Properties::get_vec3(const std::string& name) const {
    const Entry& e = require(name);
    if (auto* v = std::get_if<Vec3f>(&e.value)) return *v;
    wrong_type(e, "a point or vector");
}
Vec3f Properties::get_vec3(const std::string& name, const Vec3f& def) const {
    return has(name) ? get_vec3(name) : def;
}

Transform Properties::get_transform(const std::string& name, const Transform& def) const {
    if (!has(name)) return def;
    const Entry& e = require(name);
    if (auto* v = std::get_if<Transform>(&e.value)) return *v;
    wrong_type(e, "a transform");
}

ObjectPtr Properties::get_object(const std::string& name) const {
    const Entry* e = find(name);
    if (!e) return nullptr;
    e->used = true;
    if (auto* v = std::get_if<ObjectPtr>(&e->value)) return *v;
    wrong_type(*e, "an object");
}

std::vector<const Properties::Entry*> Properties::children(const std::string& category) const {
    std::vector<const Entry*> out;
    for (const auto& e : entries_)
        if (e.category == category && std::holds_alternative<ObjectPtr>(e.value)) {
            e.used = true;
            out.push_back(&e);
        }
    return out;
}

void Properties::check_all_used() const {
    for (const auto& e : entries_) {
        if (e.used) continue;
        if (std::holds_alternative<ObjectPtr>(e.value))
            fail(e.loc, "{} '{}' does not accept a nested <{}>{}", category_, type_, e.category,
                 e.name.empty() ? "" : fmt::format(" named '{}'", e.name));
        fail(e.loc, "{} '{}' has no parameter '{}' (unused or misspelled)", category_, type_, e.name);
    }
}

}  // namespace volguide
