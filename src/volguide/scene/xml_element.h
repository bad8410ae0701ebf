#pragma once
// One XML element with its attributes already `$name`-substituted, plus strict attribute checks.
#include <initializer_list>
#include <pugixml.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "volguide/scene/scene_parameters.h"
#include "volguide/scene/xml_file.h"

namespace volguide {

class XmlElement {
  public:
    XmlElement(const XmlFile& file, pugi::xml_node node, const SceneParameters& params);

    std::string_view tag() const { return node_.name(); }
    const SourceLocation& loc() const { return loc_; }
    pugi::xml_node node() const { return node_; }
    const XmlFile& file() const { return *file_; }

    // Every attribute must be listed in `allowed`; every one in `required` must be present.
    void expect(std::initializer_list<std::string_view> allowed,
                std::initializer_list<std::string_view> required) const;
    bool has(std::string_view name) const { return find(name) != nullptr; }
    // Substituted value; empty when absent.
    const std::string& get(std::string_view name) const;
    const std::string& require(std::string_view name) const;

    template <typename... Args>
    [[noreturn]] void fail_here(fmt::format_string<Args...> f, Args&&... args) const {
        fail(loc_, f, std::forward<Args>(args)...);
    }

  private:
    const std::string* find(std::string_view name) const;

    const XmlFile* file_;
    pugi::xml_node node_;
    SourceLocation loc_;
    std::vector<std::pair<std::string, std::string>> attrs_;
};

}  // namespace volguide
