#pragma once
// Internal to the upgrade of Mitsuba 0.x files: the one table from Mitsuba 0.6's plugins and
// parameters to what volguide reads them as (scene/legacy_table.cpp). docs/scene-format.md,
// "Mitsuba 0.6 scenes", is its user-facing form.
#include <pugixml.hpp>
#include <span>
#include <string_view>

namespace volguide::legacy {

class Dom;

// What happens to one 0.6 parameter (a named child of the plugin's element).
enum class Act {
    rename,  // read under Mitsuba 3's name: `text` when given, else snake_case of the 0.6 name
    drop,    // its value only restates 0.6's default behaviour, which is volguide's: removed
    note,    // no effect on the image in volguide: removed with the warning `text`
    reject,  // no equivalent: an error at its line, `text` says what to use instead
    hook,    // the parameter's own rule, `hook`
    plugin,  // left as written for the plugin's `finish` rule, which reads and replaces it
};

using ParamHook = void (*)(Dom& dom, pugi::xml_node object, pugi::xml_node param);
using PluginHook = void (*)(Dom& dom, pugi::xml_node object);

struct ParamRule {
    const char* name;  // Mitsuba 0.6's name; one ending in '[' stands for every name it begins
    Act act = Act::rename;
    const char* text = nullptr;
    ParamHook hook = nullptr;
};

struct PluginRule {
    const char* category;       // the XML tag: bsdf, shape, ...
    const char* type;           // Mitsuba 0.6's plugin name
    const char* to = nullptr;   // Mitsuba 3's plugin name when it differs
    const char* refuse = nullptr;  // no equivalent: the error's text (what to use instead)
    std::span<const ParamRule> params = {};  // the plugin's own parameters
    std::span<const ParamRule> family = {};  // those its base class reads (every BSDF, emitter, ...)
    PluginHook finish = nullptr;  // runs after the parameters, on Mitsuba 3's names
};

// The rule of a 0.6 plugin; nullptr when Mitsuba 0.6 has no such plugin.
const PluginRule* find_plugin(std::string_view category, std::string_view type);
// The rule of one of the plugin's parameters (its own or its family's); nullptr when 0.6's plugin
// does not read it.
const ParamRule* find_param(const PluginRule& plugin, std::string_view name);
// Every plugin of the table, in the order docs/scene-format.md lists them.
std::span<const PluginRule> plugin_table();

}  // namespace volguide::legacy
