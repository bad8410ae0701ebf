#include "volguide/scene/xml_file.h"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace volguide {

XmlFile::XmlFile(std::filesystem::path real_path, std::string display_path,
                 const SourceLocation& include_site, XmlParseMode mode)
    : path_(std::move(real_path)), display_(std::move(display_path)) {
    std::ifstream in(path_, std::ios::binary);
    if (!in) {
        if (include_site.file.empty()) fail(SourceLocation{display_, 0}, "cannot open scene file");
        fail(include_site, "cannot open included file '{}'", display_);
    }
    std::ostringstream buffer;
    buffer << in.rdbuf();
    text_ = buffer.str();

    line_starts_.push_back(0);
    for (size_t i = 0; i < text_.size(); ++i)
        if (text_[i] == '\n') line_starts_.push_back(i + 1);

    // parse_declaration keeps <?xml ...?> as a node so offsets stay meaningful; comments are skipped
    // unless the file is to be written back.
    unsigned options = pugi::parse_default | pugi::parse_declaration;
    if (mode == XmlParseMode::keep_formatting) options |= pugi::parse_comments | pugi::parse_ws_pcdata;
    pugi::xml_parse_result result = doc_.load_buffer(text_.data(), text_.size(), options);
    if (!result) {
        // pugixml reports an unclosed element as a tag mismatch at the very end of the file.
        bool at_end = result.offset + 1 >= std::ptrdiff_t(text_.size());
        if (result.status == pugi::status_end_element_mismatch && at_end)
            fail(SourceLocation{display_, line_of_offset(result.offset)},
                 "malformed XML: unexpected end of file (an element is not closed)");
        fail(SourceLocation{display_, line_of_offset(result.offset)}, "malformed XML: {}",
             result.description());
    }
    if (!doc_.document_element()) fail(SourceLocation{display_, 1}, "malformed XML: no root element");
    check_nesting_depth();
}

// The reader walks elements recursively, so a file nested deeper than any scene needs (a fuzzer
// found 10^5 levels in a few kilobytes) would overflow the stack. This walk is iterative.
void XmlFile::check_nesting_depth() const {
    std::vector<std::pair<pugi::xml_node, int>> stack{{doc_.document_element(), 1}};
    while (!stack.empty()) {
        const auto [node, depth] = stack.back();
        stack.pop_back();
        if (depth > kMaxXmlDepth)
            fail(location(node), "elements nested more than {} levels deep", kMaxXmlDepth);
        for (pugi::xml_node child : node.children())
            if (child.type() == pugi::node_element) stack.push_back({child, depth + 1});
    }
}

std::ptrdiff_t XmlFile::offset_of(const pugi::xml_node& node) const {
    auto it = offsets_.find(node.internal_object());
    return it != offsets_.end() ? it->second : node.offset_debug();
}

void XmlFile::remember_locations() {
    std::vector<pugi::xml_node> stack{doc_.document_element()};
    while (!stack.empty()) {
        pugi::xml_node node = stack.back();
        stack.pop_back();
        offsets_.emplace(node.internal_object(), node.offset_debug());
        for (pugi::xml_node child : node.children())
            if (child.type() == pugi::node_element) stack.push_back(child);
    }
}

void XmlFile::inherit_location(pugi::xml_node node, pugi::xml_node from) {
    offsets_[node.internal_object()] = offset_of(from);
}

namespace {

struct StringWriter : pugi::xml_writer {
    std::string out;
    void write(const void* data, size_t size) override { out.append(static_cast<const char*>(data), size); }
};

}  // namespace

std::string XmlFile::text() const {
    // pugixml keeps no whitespace between top-level nodes: each gets a line of its own.
    StringWriter w;
    for (pugi::xml_node node : doc_.children()) {
        node.print(w, "", pugi::format_raw);
        w.out += '\n';
    }
    return w.out;
}

std::string XmlFile::display_directory() const {
    return std::filesystem::path(display_).parent_path().string();
}

int XmlFile::line_of_offset(std::ptrdiff_t offset) const {
    if (offset < 0) return 0;
    // The last line start that is <= offset.
    auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), size_t(offset));
    return int(it - line_starts_.begin());
}

}  // namespace volguide
