#pragma once
// One parsed XML file of a scene: the pugixml document plus what is needed to turn node byte
// offsets into 1-based line numbers for error messages.
#include <filesystem>
#include <pugixml.hpp>
#include <string>
#include <unordered_map>
#include <vector>

#include "volguide/core/error.h"

namespace volguide {

// Deepest element nesting accepted in one file (a Mitsuba scene needs about 6: scene, shape, bsdf,
// texture, transform, operation).
inline constexpr int kMaxXmlDepth = 64;

// How a file is parsed: `scene` drops comments and whitespace-only text (what the reader walks);
// `keep_formatting` keeps both, for `volguide upgrade`, which writes the file back.
enum class XmlParseMode { scene, keep_formatting };

class XmlFile {
  public:
    // Reads and parses `real_path`; errors are reported as `display_path:line` (the path as the
    // user or the including file spelled it). `include_site` is where an include came from
    // (empty for the main file), used when the file cannot be read.
    XmlFile(std::filesystem::path real_path, std::string display_path, const SourceLocation& include_site,
            XmlParseMode mode = XmlParseMode::scene);

    const pugi::xml_document& document() const { return doc_; }
    // The tree may be edited (the upgrade of Mitsuba 0.x files, scene/legacy_upgrade.h); call
    // remember_locations() first so that every element keeps the line it was read from.
    pugi::xml_document& edit() { return doc_; }
    pugi::xml_node root() const { return doc_.document_element(); }
    const std::filesystem::path& path() const { return path_; }  // absolute, normalised
    std::filesystem::path directory() const { return path_.parent_path(); }
    const std::string& display_path() const { return display_; }
    std::string display_directory() const;

    int line_of_offset(std::ptrdiff_t offset) const;
    SourceLocation location(const pugi::xml_node& node) const { return {display_, line_of_offset(offset_of(node))}; }
    SourceLocation location_at(std::ptrdiff_t offset) const { return {display_, line_of_offset(offset)}; }

    // pugixml knows where a node was read only while its name is the one read; an edited tree keeps
    // the offsets here: every element's, recorded before editing, and those of the nodes an edit
    // creates, which take the location of the element they replace or complete.
    void remember_locations();
    void inherit_location(pugi::xml_node node, pugi::xml_node from);

    // The file's text as the (edited) tree now reads; with `keep_formatting` comments and
    // indentation are as read, top-level nodes on lines of their own.
    std::string text() const;

  private:
    void check_nesting_depth() const;
    std::ptrdiff_t offset_of(const pugi::xml_node& node) const;

    std::filesystem::path path_;
    std::string display_;
    std::string text_;
    std::vector<size_t> line_starts_;  // byte offset where each line begins
    pugi::xml_document doc_;
    std::unordered_map<const void*, std::ptrdiff_t> offsets_;  // see remember_locations()
};

}  // namespace volguide
