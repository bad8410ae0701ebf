#pragma once
// One parsed XML file of a scene: the pugixml document plus what is needed to turn node byte
// offsets into 1-based line numbers for error messages.
#include <filesystem>
#include <pugixml.hpp>
#include <string>
#include <vector>

#include "volguide/core/error.h"

namespace volguide {

// Deepest element nesting accepted in one file (a Mitsuba scene needs about 6: scene, shape, bsdf,
// texture, transform, operation).
inline constexpr int kMaxXmlDepth = 64;

class XmlFile {
  public:
    // Reads and parses `real_path`; errors are reported as `display_path:line` (the path as the
    // user or the including file spelled it). `include_site` is where an include came from
    // (empty for the main file), used when the file cannot be read.
    XmlFile(std::filesystem::path real_path, std::string display_path, const SourceLocation& include_site);

    const pugi::xml_document& document() const { return doc_; }
    pugi::xml_node root() const { return doc_.document_element(); }
    const std::filesystem::path& path() const { return path_; }  // absolute, normalised
    std::filesystem::path directory() const { return path_.parent_path(); }
    const std::string& display_path() const { return display_; }
    std::string display_directory() const;

    int line_of_offset(std::ptrdiff_t offset) const;
    SourceLocation location(const pugi::xml_node& node) const {
        return {display_, line_of_offset(node.offset_debug())};
    }
    SourceLocation location_at(std::ptrdiff_t offset) const { return {display_, line_of_offset(offset)}; }

  private:
    void check_nesting_depth() const;

    std::filesystem::path path_;
    std::string display_;
    std::string text_;
    std::vector<size_t> line_starts_;  // byte offset where each line begins
    pugi::xml_document doc_;
};

}  // namespace volguide
