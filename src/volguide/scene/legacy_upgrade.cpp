// The walk over a Mitsuba 0.x file: version, Mitsuba 3's own pre-2.0 rules, then every object element
// through the table (legacy_table.cpp) and every value element through 0.6's value forms
// (legacy_values.cpp).
#include "volguide/scene/legacy_upgrade.h"

#include <cctype>
#include <cstring>
#include <optional>
#include <vector>

#include "volguide/scene/legacy_dom.h"
#include "volguide/scene/legacy_rules.h"
#include "volguide/scene/legacy_table.h"
#include "volguide/scene/legacy_values.h"
#include "volguide/scene/xml_values.h"

namespace volguide {

namespace {

using namespace legacy;

struct LegacyVersion {
    int64_t major = 0, minor = 0, patch = 0;
};

std::optional<LegacyVersion> parse_legacy_version(std::string_view text) {
    auto parts = split_on(text, '.');
    if (parts.size() != 3) return std::nullopt;
    int64_t v[3];
    for (int i = 0; i < 3; ++i) {
        auto n = parse_int64(parts[size_t(i)]);
        if (!n || parts[size_t(i)].find_first_not_of("0123456789") != std::string_view::npos) return std::nullopt;
        v[i] = *n;
    }
    return LegacyVersion{v[0], v[1], v[2]};
}

// The object tags of Mitsuba 0.6 (its SceneHandler's), <subsurface> included.
bool is_legacy_object_tag(std::string_view tag) {
    for (const char* t : {"bsdf", "texture", "emitter", "shape", "sensor", "film", "rfilter", "sampler",
                          "integrator", "medium", "phase", "volume", "subsurface"})
        if (tag == t) return true;
    return false;
}

bool is_legacy_value_tag(std::string_view tag) {
    for (const char* t : {"integer", "float", "boolean", "string", "rgb", "srgb", "spectrum", "blackbody",
                          "point", "vector", "transform", "animation"})
        if (tag == t) return true;
    return false;
}

// The plugins of a category that volguide reads, for the error naming an unknown one.
std::string readable_plugins(std::string_view category) {
    std::string list;
    for (const PluginRule& p : plugin_table())
        if (category == p.category && !p.refuse) list += (list.empty() ? "" : ", ") + std::string(p.type);
    return list;
}

class Upgrader {
  public:
    Upgrader(XmlFile& file, const LegacyContext& ctx) : file_(file), dom_(file, ctx) {}

    void run() {
        pugi::xml_node root = file_.edit().document_element();
        rename_pre_2_0(root);
        dom_.refresh_ids();
        if (std::strcmp(root.name(), "scene") == 0)
            upgrade_scene(root);
        else if (is_legacy_object_tag(root.name()))
            upgrade_object(root);
        // Anything else is reported by the reader (the root must be a scene or an object).
        strict_normals_effect(dom_, root);
        dom_.set_attr(root, "version", "3.0.0");
    }

  private:
    // Mitsuba 3's renames of pre-2.0 files that are not about one plugin: <lookAt>, and ids starting
    // with '_' (reserved since 2.0).
    void rename_pre_2_0(pugi::xml_node node) {
        for (pugi::xml_node child : node.children()) {
            if (child.type() != pugi::node_element) continue;
            if (std::strcmp(child.name(), "lookAt") == 0) dom_.retag(child, "lookat");
            if (pugi::xml_attribute id = child.attribute("id"); id && id.value()[0] == '_') {
                const std::string renamed = std::string("ID") + id.value() + "__UPGR";
                if (std::strcmp(child.name(), "ref") != 0)
                    dom_.warn(child, "id \"{}\" is reserved since Mitsuba 2: renamed \"{}\" (as Mitsuba 3 does)",
                              id.value(), renamed);
                id.set_value(renamed.c_str());
            }
            rename_pre_2_0(child);
        }
    }

    void upgrade_scene(pugi::xml_node scene) {
        for (pugi::xml_node child : elements(scene)) {
            const std::string_view tag = child.name();
            if (tag == "null")
                dom_.remove(child);  // 0.6's placeholder element, which creates nothing
            else if (is_legacy_object_tag(tag))
                upgrade_object(child);
            else if (is_legacy_value_tag(tag))
                convert_value(dom_, child);
        }
    }

    static std::vector<pugi::xml_node> elements(pugi::xml_node node) {
        std::vector<pugi::xml_node> out;
        for (pugi::xml_node c : node.children())
            if (c.type() == pugi::node_element) out.push_back(c);
        return out;
    }

    const PluginRule& rule_of(pugi::xml_node object) const {
        const std::string category = object.name(), type = dom_.attr(object, "type");
        const PluginRule* rule = find_plugin(category, type);
        if (!rule) {
            if (!object.attribute("type")) dom_.fail(object, "<{}> is missing the required attribute 'type'", category);
            dom_.fail(object,
                      "Mitsuba 0.6 has no {} plugin '{}' (a fork's own?): a 0.6 file may use {} (docs/scene-format.md, "
                      "\"Mitsuba 0.6 scenes\"); volguide's own plugins are read from 3.0 files",
                      category, type, readable_plugins(category).empty() ? "none" : readable_plugins(category));
        }
        if (rule->refuse) dom_.fail(object, "Mitsuba 0.6's {} '{}': {}", category, type, rule->refuse);
        return *rule;
    }

    void upgrade_object(pugi::xml_node object) {
        const PluginRule& rule = rule_of(object);
        for (pugi::xml_node child : elements(object)) upgrade_child(rule, object, child);
        if (rule.finish) rule.finish(dom_, object);
        if (rule.to) dom_.set_attr(object, "type", rule.to);
    }

    void upgrade_child(const PluginRule& rule, pugi::xml_node object, pugi::xml_node child) {
        const std::string_view tag = child.name();
        if (tag == "null") {
            dom_.remove(child);
        } else if (is_legacy_object_tag(tag) || tag == "ref") {
            if (tag != "ref") upgrade_object(child);
            if (child.attribute("name")) apply(rule, object, child, /*is_object=*/true);
        } else if (is_legacy_value_tag(tag)) {
            convert_value(dom_, child);
            apply(rule, object, child, /*is_object=*/false);
        }
        // <include>, <default>, <alias>, ...: the reader's (a misplaced one is its error).
    }

    // One named child through the plugin's parameter rules.
    void apply(const PluginRule& rule, pugi::xml_node object, pugi::xml_node child, bool is_object) {
        const std::string name = dom_.attr(child, "name");
        const ParamRule* p = find_param(rule, name);
        if (!p) {
            if (is_object) {
                // 0.6 hands a nested object to its parent by kind; only a few roles go by name.
                dom_.strip_name(child);
                return;
            }
            dom_.warn(child, "Mitsuba 0.6's {} '{}' does not read a parameter '{}': ignored, as 0.6 ignores it",
                      rule.category, rule.type, name);
            dom_.remove(child);
            return;
        }
        switch (p->act) {
            case Act::rename: dom_.set_attr(child, "name", p->text ? std::string(p->text) : snake_case(name)); break;
            case Act::drop: dom_.remove(child); break;
            case Act::note:
                dom_.warn(child, "{}", p->text);
                dom_.remove(child);
                break;
            case Act::reject: dom_.fail(child, "Mitsuba 0.6's {} '{}': {}", rule.category, rule.type, p->text);
            case Act::hook: p->hook(dom_, object, child); break;
            case Act::plugin: break;
        }
    }

    XmlFile& file_;
    Dom dom_;
};

}  // namespace

std::string snake_case(std::string_view text) {
    // Mitsuba 3's loop, quirks included: after a run of capitals the next character is skipped.
    std::string name(text);
    for (size_t i = 0; i + 1 < name.size(); ++i) {
        auto lower = [](char c) { return std::islower(static_cast<unsigned char>(c)) != 0; };
        auto upper = [](char c) { return std::isupper(static_cast<unsigned char>(c)) != 0; };
        if (lower(name[i]) && upper(name[i + 1])) {
            name.insert(i + 1, 1, '_');
            i += 2;
            while (i < name.size() && upper(name[i])) {
                name[i] = char(std::tolower(static_cast<unsigned char>(name[i])));
                ++i;
            }
        }
    }
    return name;
}

bool is_legacy_file(const XmlFile& file, const SceneParameters& params) {
    const std::string text = params.substitute(file.root().attribute("version").value(), file.location(file.root()));
    auto v = parse_legacy_version(text);
    return v && v->major == 0 && unsupported_version_message(text).empty();
}

std::string unsupported_version_message(std::string_view text) {
    auto v = parse_legacy_version(text);
    if (!v) return {};
    const std::string readable = "volguide reads versions 0.4.0 to 0.6.x (Mitsuba 0.4 to 0.6), 2.x and 3.x";
    if (v->major == 0 && v->minor < 4)
        return fmt::format("scene format version {} predates Mitsuba 0.4, whose format changed (cameras, "
                           "luminaires): {}; let Mitsuba 0.6 upgrade the file first",
                           text, readable);
    if (v->major == 0 && v->minor > 6) return fmt::format("scene format version {} is not a Mitsuba release: {}", text, readable);
    if (v->major == 0 || v->major == 2 || v->major == 3) return {};
    return fmt::format("scene format version {} is not supported ({})", text, readable);
}

void add_legacy_default_integrator(XmlFile& main) {
    pugi::xml_node scene = main.edit().document_element();
    if (std::strcmp(scene.name(), "scene") != 0) return;
    LegacyContext ctx;
    Dom dom(main, ctx);
    pugi::xml_node first;
    for (pugi::xml_node c : scene.children())
        if (c.type() == pugi::node_element) {
            first = c;
            break;
        }
    pugi::xml_node integrator = dom.add(scene, "integrator", scene, first);
    integrator.append_attribute("type").set_value("direct");
}

void upgrade_legacy_file(XmlFile& file, const LegacyContext& ctx) {
    file.remember_locations();
    Upgrader(file, ctx).run();
}

}  // namespace volguide
