#include "volguide/scene/legacy_dom.h"

#include <cctype>
#include <cstring>

#include "volguide/scene/xml_values.h"

namespace volguide::legacy {

namespace {

void collect_ids(pugi::xml_node node, std::map<std::string, pugi::xml_node>& ids) {
    for (pugi::xml_node child : node.children()) {
        if (child.type() != pugi::node_element) continue;
        // <ref> and <alias> name an id; they do not declare one.
        const std::string_view tag = child.name();
        if (tag != "ref" && tag != "alias" && child.attribute("id")) ids.emplace(child.attribute("id").value(), child);
        collect_ids(child, ids);
    }
}

// The whitespace text right before `node`, when the file keeps its formatting.
pugi::xml_node indentation_before(pugi::xml_node node) {
    pugi::xml_node prev = node.previous_sibling();
    return prev && prev.type() == pugi::node_pcdata && trim(prev.value()).empty() ? prev : pugi::xml_node();
}

}  // namespace

Dom::Dom(XmlFile& file, const LegacyContext& ctx) : file_(file), ctx_(ctx) {
    refresh_ids();
}

void Dom::refresh_ids() {
    ids_.clear();
    pugi::xml_node root = file_.edit().document_element();
    collect_ids(root, ids_);
    if (root.attribute("id")) ids_.emplace(root.attribute("id").value(), root);
}

std::string Dom::attr(pugi::xml_node node, const char* name) const {
    pugi::xml_attribute a = node.attribute(name);
    if (!a) return {};
    return ctx_.params ? ctx_.params->substitute(a.value(), loc(node)) : std::string(a.value());
}

pugi::xml_node Dom::add(pugi::xml_node parent, const char* tag, pugi::xml_node origin, pugi::xml_node before) {
    // Indented as the element it is placed before, or as the last child element when appended (then
    // before the whitespace that closes the parent's content).
    pugi::xml_node like = before;
    for (pugi::xml_node c = parent.last_child(); !like && c; c = c.previous_sibling())
        if (c.type() == pugi::node_element) like = c;
    const pugi::xml_node indent = like ? indentation_before(like) : pugi::xml_node();
    pugi::xml_node anchor = before;
    if (!anchor && parent.last_child().type() == pugi::node_pcdata && trim(parent.last_child().value()).empty())
        anchor = parent.last_child();
    pugi::xml_node node = anchor ? parent.insert_child_before(tag, anchor) : parent.append_child(tag);
    file_.inherit_location(node, origin);
    if (indent) {
        if (before)
            parent.insert_child_after(pugi::node_pcdata, node).set_value(indent.value());
        else
            parent.insert_child_before(pugi::node_pcdata, node).set_value(indent.value());
    }
    return node;
}

pugi::xml_node Dom::add_value(pugi::xml_node parent, const char* tag, const std::string& name,
                              const std::string& value, pugi::xml_node origin, pugi::xml_node before) {
    pugi::xml_node node = add(parent, tag, origin, before);
    node.append_attribute("name").set_value(name.c_str());
    node.append_attribute("value").set_value(value.c_str());
    return node;
}

void Dom::remove(pugi::xml_node node) {
    if (pugi::xml_node indent = indentation_before(node)) node.parent().remove_child(indent);
    node.parent().remove_child(node);
}

void Dom::set_attr(pugi::xml_node node, const char* name, const std::string& value) {
    pugi::xml_attribute a = node.attribute(name);
    if (!a) a = node.append_attribute(name);
    a.set_value(value.c_str());
}

void Dom::retag(pugi::xml_node node, const char* tag) {
    file_.inherit_location(node, node);  // pugixml forgets a renamed node's offset
    node.set_name(tag);
}

void Dom::strip_name(pugi::xml_node child) {
    stripped_names_[child.internal_object()] = child.attribute("name").value();
    child.remove_attribute("name");
}

std::string Dom::stripped_name(pugi::xml_node child) const {
    auto it = stripped_names_.find(child.internal_object());
    return it == stripped_names_.end() ? std::string() : it->second;
}

pugi::xml_node Dom::param(pugi::xml_node object, std::string_view name) const {
    for (pugi::xml_node c : object.children())
        if (c.type() == pugi::node_element && name == c.attribute("name").value()) return c;
    return {};
}

double Dom::number(pugi::xml_node value) const {
    const std::string_view tag = value.name();
    if (tag != "float" && tag != "integer")
        fail(value, "'{}' must be a number here (got <{}>)", value.attribute("name").value(), tag);
    const std::string text = attr(value, "value");
    auto v = parse_double(text, /*allow_infinity=*/true);
    if (!v) fail(value, "<{}>: could not parse \"{}\" as a number", tag, text);
    return *v;
}

std::array<double, 3> Dom::vec3(pugi::xml_node value) const {
    const std::string_view tag = value.name();
    if (tag != "point" && tag != "vector")
        fail(value, "'{}' must be a <point> here (got <{}>)", value.attribute("name").value(), tag);
    std::array<double, 3> out{};
    if (value.attribute("value")) {
        const std::string text = attr(value, "value");  // the tokens view it
        const auto tokens = tokenize_list(text);
        if (tokens.size() != 1 && tokens.size() != 3)
            fail(value, "<{}>: 'value' needs 1 or 3 numbers (got \"{}\")", tag, text);
        for (size_t i = 0; i < 3; ++i) {
            auto x = parse_double(tokens[tokens.size() == 1 ? 0 : i]);
            if (!x) fail(value, "<{}>: could not parse \"{}\" as a finite number", tag, tokens[i]);
            out[i] = *x;
        }
        return out;
    }
    const char* names[3] = {"x", "y", "z"};
    for (size_t i = 0; i < 3; ++i) {
        auto x = parse_double(attr(value, names[i]));
        if (!x) fail(value, "<{}>: '{}' must be a finite number (got \"{}\")", tag, names[i], attr(value, names[i]));
        out[i] = *x;
    }
    return out;
}

bool Dom::is_constant_color(pugi::xml_node value) const {
    const std::string_view tag = value.name();
    if (tag == "rgb" || tag == "float" || tag == "integer") return true;
    return tag == "spectrum" && !value.attribute("type") && !value.attribute("filename") &&
           tokenize_list(attr(value, "value")).size() == 1;
}

Rgb Dom::color(pugi::xml_node value) const {
    if (!is_constant_color(value))
        fail(value, "'{}' must be a constant colour here (<rgb>, <spectrum>, <float>; got <{}>)",
             value.attribute("name").value(), value.name());
    const std::string text = attr(value, "value");
    std::vector<double> v;
    for (std::string_view t : tokenize_list(text)) {
        auto x = parse_double(t);
        if (!x) fail(value, "<{}>: could not parse \"{}\" as a finite number", value.name(), t);
        v.push_back(*x);
    }
    if (v.size() == 1) return {v[0], v[0], v[0]};
    if (v.size() == 3) return {v[0], v[1], v[2]};
    fail(value, "<{}> needs one or three values (got \"{}\")", value.name(), text);
}

std::string Dom::string(pugi::xml_node value) const {
    if (std::strcmp(value.name(), "string") != 0)
        fail(value, "'{}' must be a <string> (got <{}>)", value.attribute("name").value(), value.name());
    return attr(value, "value");
}

bool Dom::boolean(pugi::xml_node value) const {
    if (std::strcmp(value.name(), "boolean") != 0)
        fail(value, "'{}' must be a <boolean> (got <{}>)", value.attribute("name").value(), value.name());
    auto b = parse_bool(attr(value, "value"));
    if (!b) fail(value, "<boolean>: \"{}\" must be \"true\" or \"false\"", attr(value, "value"));
    return *b;
}

void Dom::note_fixed_parameter(pugi::xml_node value) const {
    if (!for_mitsuba3()) return;
    for (pugi::xml_attribute a : value.attributes())
        if (std::strchr(a.value(), '$'))
            warn(value, "'{}' is \"{}\" (\"{}\" here) and enters a computed value: the upgraded file holds the "
                        "number, not the parameter",
                 value.attribute("name").value(), a.value(), attr(value, a.name()));
}

pugi::xml_node Dom::by_id(const std::string& id) const {
    auto it = ids_.find(id);
    return it == ids_.end() ? pugi::xml_node() : it->second;
}

std::string Dom::object_tag(pugi::xml_node child) const {
    if (std::strcmp(child.name(), "ref") != 0) return child.name();
    pugi::xml_node target = by_id(attr(child, "id"));
    return target ? target.name() : std::string();
}

std::optional<std::string> Dom::resolve(const std::string& name) const {
    if (!ctx_.resolver) return std::nullopt;
    auto r = ctx_.resolver->resolve(name, {file_.directory(), file_.display_directory()});
    if (!r) return std::nullopt;
    return r->path.string();
}

std::string lowercase(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool is_float_image(const std::string& filename) {
    const std::string l = lowercase(filename);
    for (std::string_view ext : {".exr", ".hdr", ".rgbe", ".pfm"})
        if (std::string_view(l).ends_with(ext)) return true;
    return false;
}

std::string float_text(double v) {
    return fmt::format("{}", float(v));
}

std::string rgb_text(const Rgb& c) {
    return fmt::format("{} {} {}", float(c[0]), float(c[1]), float(c[2]));
}

}  // namespace volguide::legacy
