#pragma once
// Internal to the upgrade of Mitsuba 0.x files (scene/legacy_upgrade.h): the edits and reads its rules
// make on one file's tree, with every error and warning at the line of the element concerned.
#include <fmt/format.h>

#include <array>
#include <map>
#include <optional>
#include <pugixml.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "volguide/core/error.h"
#include "volguide/core/log.h"
#include "volguide/scene/legacy_upgrade.h"

namespace volguide::legacy {

using Rgb = std::array<double, 3>;

class Dom {
  public:
    Dom(XmlFile& file, const LegacyContext& ctx);

    const LegacyContext& ctx() const { return ctx_; }
    bool for_mitsuba3() const { return ctx_.target == UpgradeTarget::mitsuba3; }
    SourceLocation loc(pugi::xml_node node) const { return file_.location(node); }

    // An attribute with `$name` substituted (empty when absent).
    std::string attr(pugi::xml_node node, const char* name) const;

    template <typename... Args>
    [[noreturn]] void fail(pugi::xml_node node, fmt::format_string<Args...> f, Args&&... args) const {
        volguide::fail(loc(node), f, std::forward<Args>(args)...);
    }
    template <typename... Args>
    void warn(pugi::xml_node node, fmt::format_string<Args...> f, Args&&... args) const {
        volguide::warn(loc(node), f, std::forward<Args>(args)...);
    }

    // ---- edits ----------------------------------------------------------------------------------
    // A new element <tag> in `parent` before `before` (appended when null), indented as its siblings,
    // located at `origin`'s line.
    pugi::xml_node add(pugi::xml_node parent, const char* tag, pugi::xml_node origin,
                       pugi::xml_node before = pugi::xml_node());
    // A new value element <tag name="name" value="value"/> (see add).
    pugi::xml_node add_value(pugi::xml_node parent, const char* tag, const std::string& name,
                             const std::string& value, pugi::xml_node origin,
                             pugi::xml_node before = pugi::xml_node());
    // Removes `node` with the indentation before it.
    void remove(pugi::xml_node node);
    void set_attr(pugi::xml_node node, const char* name, const std::string& value);
    // The element read as `tag` from now on (keeps its attributes, children and line).
    void retag(pugi::xml_node node, const char* tag);
    // A nested object's `name` that 0.6's plugin does not read by name: 0.6 hands such a child to its
    // parent by kind, as Mitsuba 3 does an unnamed one. The name stays known to the plugin's rule.
    void strip_name(pugi::xml_node child);
    std::string stripped_name(pugi::xml_node child) const;

    // ---- the parameters of an object element (children with a `name`) ----------------------------
    pugi::xml_node param(pugi::xml_node object, std::string_view name) const;
    // Value parameters read as numbers, colours, strings, booleans; an error at the parameter's line
    // when it is not of that kind (e.g. a texture where 0.6 takes a spectrum).
    double number(pugi::xml_node value) const;
    Rgb color(pugi::xml_node value) const;
    std::string string(pugi::xml_node value) const;
    bool boolean(pugi::xml_node value) const;
    // A <point> or <vector> (value="x y z" or x, y, z attributes).
    std::array<double, 3> vec3(pugi::xml_node value) const;
    // Whether a value parameter is a constant colour (rgb, one-valued spectrum, float, integer).
    bool is_constant_color(pugi::xml_node value) const;
    // A value with `$name` that a computed value replaces: the written file keeps the value.
    void note_fixed_parameter(pugi::xml_node value) const;

    // Reads the file's ids again (after they were renamed).
    void refresh_ids();
    // An integrator's strictNormals=true, whose effect depends on the file's shapes (strict_normals).
    void set_strict_normals(pugi::xml_node param) { strict_normals_ = loc(param); }
    const std::optional<SourceLocation>& strict_normals() const { return strict_normals_; }

    // The element with id `id` in this file (null when it is declared elsewhere).
    pugi::xml_node by_id(const std::string& id) const;
    // The tag of the object a child stands for: its own for a nested object, the referenced one's
    // for a <ref> (empty when the reference leads out of this file).
    std::string object_tag(pugi::xml_node child) const;
    // A data file the rules read, looked up as the reader looks up file names (nullopt: not found).
    std::optional<std::string> resolve(const std::string& name) const;

  private:
    XmlFile& file_;
    const LegacyContext& ctx_;
    std::map<std::string, pugi::xml_node> ids_;
    std::map<const void*, std::string> stripped_names_;
    std::optional<SourceLocation> strict_normals_;
};

// A number as the shortest text that reads back as the same single-precision float (volguide and
// Mitsuba 3 read scene numbers into floats).
std::string float_text(double v);
std::string lowercase(std::string s);
// Whether an image file holds floating-point values (OpenEXR, Radiance, PFM), by its extension: 0.6 reads
// those linearly and 8-bit ones through the sRGB curve unless told otherwise.
bool is_float_image(const std::string& filename);
std::string rgb_text(const Rgb& c);

}  // namespace volguide::legacy
