#include "volguide/scene/xml_element.h"

#include <algorithm>

namespace volguide {

XmlElement::XmlElement(const XmlFile& file, pugi::xml_node node, const SceneParameters& params)
    : file_(&file), node_(node), loc_(file.location(node)) {
    for (pugi::xml_attribute a : node.attributes())
        attrs_.emplace_back(a.name(), params.substitute(a.value(), loc_));
}

const std::string* XmlElement::find(std::string_view name) const {
    for (const auto& [k, v] : attrs_)
        if (k == name) return &v;
    return nullptr;
}

const std::string& XmlElement::get(std::string_view name) const {
    static const std::string empty;
    const std::string* v = find(name);
    return v ? *v : empty;
}

const std::string& XmlElement::require(std::string_view name) const {
    const std::string* v = find(name);
    if (!v) fail_here("<{}> is missing the required attribute '{}'", tag(), name);
    return *v;
}

void XmlElement::expect(std::initializer_list<std::string_view> allowed,
                        std::initializer_list<std::string_view> required) const {
    for (const auto& [k, v] : attrs_)
        if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
            fail_here("unexpected attribute '{}' in <{}>", k, tag());
    for (std::string_view r : required)
        if (!find(r)) fail_here("<{}> is missing the required attribute '{}'", tag(), r);
}

}  // namespace volguide
