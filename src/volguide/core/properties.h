#pragma once
// Typed, location-aware parameter list of one scene object: what the XML reader produces and
// what every plugin constructor consumes. Every getter marks its parameter as used; after
// construction the loader calls check_all_used(), so a misspelled or unsupported parameter is an
// error naming its file and line instead of being silently ignored.
#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/core/error.h"
#include "volguide/core/object.h"
#include "volguide/core/transform.h"
#include "volguide/core/vec.h"

namespace volguide {

class Properties {
public:
    using Value = std::variant<bool, int64_t, double, std::string, Color3, Vec3f, Transform, ObjectPtr>;

    struct Entry {
        std::string name;      // the XML `name` attribute; "" for an unnamed child object
        std::string category;  // XML tag: "float", "rgb", ..., or for objects "bsdf", "emitter", ...
        Value value;
        SourceLocation loc;
        mutable bool used = false;
    };

    Properties() = default;
    Properties(std::string category, std::string plugin_type, SourceLocation loc)
        : category_(std::move(category)), type_(std::move(plugin_type)), loc_(std::move(loc)) {}

    const std::string& category() const { return category_; }  // "bsdf", "shape", ...
    const std::string& type() const { return type_; }          // "diffuse", "obj", ...
    const std::string& id() const { return id_; }
    void set_id(std::string id) { id_ = std::move(id); }
    const SourceLocation& location() const { return loc_; }

    // Adding a value whose name already exists is an input error (Mitsuba rejects duplicates).
    void set(std::string name, std::string category, Value value, SourceLocation loc);
    bool has(const std::string& name) const;
    // Location of a parameter (or of the object itself when absent), for error messages.
    const SourceLocation& location_of(const std::string& name) const;

    // Required getters throw InputError when the parameter is missing or has the wrong type.
    bool get_bool(const std::string& name) const;
    bool get_bool(const std::string& name, bool def) const;
    int64_t get_int(const std::string& name) const;
    int64_t get_int(const std::string& name, int64_t def) const;
    // Accepts integer and float values.
    float get_float(const std::string& name) const;
    float get_float(const std::string& name, float def) const;
    std::string get_string(const std::string& name) const;
    std::string get_string(const std::string& name, const std::string& def) const;
    // Accepts rgb, spectrum (already converted to RGB) and float (gray) values.
    Color3 get_color(const std::string& name) const;
    Color3 get_color(const std::string& name, const Color3& def) const;
    // point and vector values.
    Vec3f get_vec3(const std::string& name) const;
    Vec3f get_vec3(const std::string& name, const Vec3f& def) const;
    Transform get_transform(const std::string& name, const Transform& def = Transform()) const;

    // A named child object (nested or by reference); nullptr when absent.
    ObjectPtr get_object(const std::string& name) const;
    const Entry* find(const std::string& name) const;
    // All child objects of one XML category ("bsdf", "emitter", ...), named or not, in file order.
    std::vector<const Entry*> children(const std::string& category) const;
    const std::vector<Entry>& entries() const { return entries_; }
    // Marks a parameter used without reading it (e.g. accepted but ignored with a warning).
    void mark_used(const std::string& name) const;

    // Throws InputError at the first parameter or child object nobody asked for.
    void check_all_used() const;

    template <typename... Args>
    [[noreturn]] void fail_at(const std::string& param, fmt::format_string<Args...> f, Args&&... args) const {
        fail(location_of(param), f, std::forward<Args>(args)...);
    }
    template <typename... Args>
    [[noreturn]] void fail_here(fmt::format_string<Args...> f, Args&&... args) const {
        fail(loc_, f, std::forward<Args>(args)...);
    }

private:
    const Entry& require(const std::string& name) const;
    [[noreturn]] void wrong_type(const Entry& e, const char* expected) const;

    std::string category_, type_, id_;
    SourceLocation loc_;
    std::vector<Entry> entries_;
};

// Typed child access: nullptr when absent; an input error when the object has the wrong kind.
template <typename T>
std::shared_ptr<T> get_object_as(const Properties& props, const std::string& name) {
    ObjectPtr obj = props.get_object(name);
    if (!obj) return nullptr;
    auto typed = std::dynamic_pointer_cast<T>(obj);
    if (!typed) props.fail_at(name, "parameter '{}' refers to an object of the wrong kind", name);
    return typed;
}

}  // namespace volguide
