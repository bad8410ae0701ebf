#include "volguide/scene/xml_reader.h"

#include <array>
#include <cctype>
#include <filesystem>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "volguide/core/log.h"
#include "volguide/scene/file_resolver.h"
#include "volguide/scene/legacy_upgrade.h"
#include "volguide/scene/scene_parameters.h"
#include "volguide/scene/xml_element.h"
#include "volguide/scene/xml_file.h"
#include "volguide/scene/xml_properties.h"
#include "volguide/scene/xml_values.h"

namespace volguide {

namespace fs = std::filesystem;

namespace {

// Longest chain of <include>s (the main file counts as the first); scenes use two or three levels.
constexpr size_t kMaxIncludeDepth = 32;

// XML tags that create plugin objects; the tag is the factory category.
bool is_object_tag(std::string_view tag) {
    static constexpr std::array<std::string_view, 12> tags = {"bsdf",       "texture", "emitter", "shape",
                                                              "sensor",     "film",    "rfilter", "sampler",
                                                              "integrator", "medium",  "phase",   "volume"};
    for (auto t : tags)
        if (t == tag) return true;
    return false;
}

std::string_view trim_front(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    return s;
}

bool reserved_name(const std::string& s) {
    return !s.empty() && s.front() == '_';
}

// Mitsuba writes versions as "major.minor.patch"; volguide reads the 2.x and 3.x formats, and the 0.x
// formats of Mitsuba 0.4 to 0.6, which are upgraded (legacy_upgrade.h) before this check sees them.
void check_version(const XmlElement& el) {
    const std::string& v = el.require("version");
    auto parts = split_on(v, '.');
    bool ok = parts.size() == 3;
    for (auto p : parts)
        ok = ok && parse_int64(p) && p.find_first_not_of("0123456789") == std::string_view::npos;
    if (!ok) el.fail_here("could not parse version \"{}\" (expected major.minor.patch)", v);
    const std::string unsupported = unsupported_version_message(v);
    if (!unsupported.empty()) el.fail_here("{}", unsupported);
}

class Reader {
  public:
    Reader(const std::string& path, const LoadOptions& options)
        : params_(options.defines), resolver_(main_dir(path)), main_display_(path), xml_files_(options.xml_files) {}

    SceneGraph run() {
        XmlFile& main = collect_main(XmlParseMode::scene);
        if (xml_files_)
            for (const auto& [key, file] : files_) xml_files_->push_back(key.string());
        upgrade_defaults(main);
        for (auto& [key, file] : files_)
            if (is_legacy_file(*file, params_)) upgrade_legacy_file(*file, context(UpgradeTarget::volguide));
        read_root(main);
        return std::move(graph_);
    }

    // The main file in Mitsuba 3's form, as text (volguide upgrade); its includes are read, not written.
    std::string upgrade_main() {
        XmlFile& main = collect_main(XmlParseMode::keep_formatting);
        if (!is_legacy_file(main, params_)) {
            const std::string version = main.root().attribute("version").value();
            const std::string unsupported = unsupported_version_message(version);
            fail(main.location(main.root()), "{}", unsupported.empty()
                                                       ? fmt::format("not a Mitsuba 0.x file (version \"{}\"): nothing to upgrade", version)
                                                       : unsupported);
        }
        for (auto& [key, file] : files_)
            if (file.get() != &main && is_legacy_file(*file, params_))
                warn(SourceLocation{file->display_path(), 1},
                     "an included Mitsuba 0.x file is not upgraded with the file including it: upgrade it too");
        upgrade_defaults(main);
        upgrade_legacy_file(main, context(UpgradeTarget::mitsuba3));
        return main.text();
    }

  private:
    // Pass 1 over the main file and its includes: defaults, paths and every file loaded.
    XmlFile& collect_main(XmlParseMode mode) {
        std::error_code ec;
        if (!fs::is_regular_file(main_display_, ec))
            fail(SourceLocation{main_display_, 0}, "scene file not found");
        fs::path real = fs::absolute(main_display_).lexically_normal();
        XmlFile& main = load(real, main_display_, SourceLocation{}, mode);

        include_stack_.push_back({key_of(real), main_display_});
        collect(main);
        include_stack_.pop_back();
        params_.check_overrides(SourceLocation{main_display_, 0});
        return main;
    }

    LegacyContext context(UpgradeTarget target) const { return {target, &params_, &resolver_}; }

    // The defaults of a 0.x main scene that differ from Mitsuba 3's (add_legacy_default_integrator):
    // decided over every file of the scene, before any is rewritten.
    void upgrade_defaults(XmlFile& main) {
        if (!is_legacy_file(main, params_)) return;
        for (auto& [key, file] : files_)
            for (pugi::xml_node c : file->root().children())
                if (std::string_view(c.name()) == "integrator") return;
        add_legacy_default_integrator(main);
    }

    static FileResolver::Dir main_dir(const std::string& path) {
        return {fs::absolute(path).lexically_normal().parent_path(), fs::path(path).parent_path().string()};
    }
    static fs::path key_of(const fs::path& p) {
        std::error_code ec;
        fs::path k = fs::weakly_canonical(p, ec);
        return ec ? p : k;
    }
    FileResolver::Dir dir_of(const XmlFile& f) const { return {f.directory(), f.display_directory()}; }

    XmlFile& load(const fs::path& real, const std::string& display, const SourceLocation& site,
                  XmlParseMode mode = XmlParseMode::scene) {
        fs::path key = key_of(real);
        auto it = files_.find(key);
        if (it == files_.end())
            it = files_.emplace(key, std::make_unique<XmlFile>(real, display, site, mode)).first;
        return *it->second;
    }

    // ---- pass 1: defaults, <path> directories and the include tree ------------------------------

    void collect(const XmlFile& f) {
        collect_defaults(f, f.root());
        collect_paths_and_includes(f, f.root());
    }

    void collect_defaults(const XmlFile& f, pugi::xml_node node) {
        for (pugi::xml_node child : node.children()) {
            if (child.type() != pugi::node_element) continue;
            if (std::string_view(child.name()) == "default") {
                SourceLocation loc = f.location(child);
                for (pugi::xml_attribute a : child.attributes()) {
                    std::string_view n = a.name();
                    if (n != "name" && n != "value") fail(loc, "unexpected attribute '{}' in <default>", n);
                }
                if (!child.attribute("name")) fail(loc, "<default> is missing the required attribute 'name'");
                if (!child.attribute("value"))
                    fail(loc, "<default> is missing the required attribute 'value'");
                params_.declare(child.attribute("name").value(), child.attribute("value").value(), loc);
            } else {
                collect_defaults(f, child);
            }
        }
    }

    void collect_paths_and_includes(const XmlFile& f, pugi::xml_node node) {
        for (pugi::xml_node child : node.children()) {
            if (child.type() != pugi::node_element) continue;
            std::string_view tag = child.name();
            if (tag == "path") {
                XmlElement el(f, child, params_);
                el.expect({"value"}, {"value"});
                auto dir = resolver_.resolve(el.get("value"), dir_of(f), /*want_directory=*/true);
                if (!dir) el.fail_here("<path>: directory \"{}\" not found", el.get("value"));
                resolver_.add_search_dir({dir->path, dir->display});
            } else if (tag == "include") {
                XmlElement el(f, child, params_);
                el.expect({"filename"}, {"filename"});
                const std::string& name = el.get("filename");
                auto target = resolver_.resolve(name, dir_of(f));
                if (!target) el.fail_here("included file \"{}\" not found", name);
                // Cycles are caught below; a long acyclic chain is bounded too (each level recurses).
                if (include_stack_.size() >= kMaxIncludeDepth)
                    el.fail_here("includes nested more than {} files deep", kMaxIncludeDepth);
                fs::path key = key_of(target->path);
                for (size_t i = 0; i < include_stack_.size(); ++i)
                    if (include_stack_[i].first == key) {
                        std::string chain;
                        for (size_t j = i; j < include_stack_.size(); ++j)
                            chain += include_stack_[j].second + " -> ";
                        el.fail_here("cyclic include: {}{}", chain, target->display);
                    }
                const XmlFile& inc = load(target->path, target->display, el.loc());
                includes_[{&f, child.offset_debug()}] = &inc;
                include_stack_.push_back({key, target->display});
                collect(inc);
                include_stack_.pop_back();
            } else if (tag != "default") {
                collect_paths_and_includes(f, child);
            }
        }
    }

    // ---- pass 2: records ------------------------------------------------------------------------

    void read_root(const XmlFile& f) {
        XmlElement root(f, f.root(), params_);
        if (root.tag() != "scene") root.fail_here("the root element must be <scene> (got <{}>)", root.tag());
        root.expect({"version"}, {"version"});
        check_version(root);
        graph_.nodes.push_back({"scene", Properties("scene", "scene", root.loc()), {}});
        read_children(f, f.root(), 0, /*in_scene=*/true, /*within_emitter=*/false);
    }

    void read_children(const XmlFile& f, pugi::xml_node xml, int parent, bool in_scene, bool within_emitter) {
        for (pugi::xml_node child : xml.children()) {
            if (child.type() == pugi::node_pcdata || child.type() == pugi::node_cdata) {
                // Report the line of the text itself, not of the whitespace before it.
                std::string_view text = child.value();
                std::ptrdiff_t skip = std::ptrdiff_t(text.size() - trim_front(text).size());
                fail(f.location_at(child.offset_debug() + skip), "unexpected text \"{}\" inside <{}>",
                     trim(text), xml.name());
            }
            if (child.type() != pugi::node_element) continue;
            read_element(f, child, parent, in_scene, within_emitter);
        }
    }

    void read_element(const XmlFile& f, pugi::xml_node node, int parent, bool in_scene, bool within_emitter) {
        std::string_view tag = node.name();
        if (tag == "default") return;  // validated and collected in pass 1
        XmlElement el(f, node, params_);
        if (tag == "path") {
            if (!in_scene) el.fail_here("<path> may only appear directly inside <scene>");
            return;  // added to the resolver in pass 1
        }
        if (tag == "include") {
            read_include(f, el, parent, in_scene, within_emitter);
        } else if (tag == "ref") {
            el.expect({"id", "name"}, {"id"});
            if (reserved_name(el.get("name"))) el.fail_here("names starting with '_' are reserved");
            graph_.nodes[size_t(parent)].children.push_back({-1, el.get("id"), el.get("name"), el.loc()});
            if (node.first_child()) el.fail_here("<ref> cannot have children");
        } else if (tag == "alias") {
            el.expect({"id", "as"}, {"id", "as"});
            auto it = graph_.ids.find(el.get("id"));
            if (it == graph_.ids.end()) el.fail_here("<alias>: unknown id \"{}\"", el.get("id"));
            register_id(el.get("as"), it->second, el);
        } else if (tag == "spectrum" && el.has("type")) {
            read_object(f, el, "texture", parent);  // a spectrum plugin is a texture in Mitsuba 3
        } else if (is_value_tag(tag)) {
            PropertyContext ctx{&params_, &resolver_, within_emitter};
            add_value_property(el, graph_.nodes[size_t(parent)].props, ctx);
        } else if (is_transform_op_tag(tag)) {
            el.fail_here("<{}> can only appear inside <transform>", tag);
        } else if (is_object_tag(tag)) {
            read_object(f, el, std::string(tag), parent);
        } else if (tag == "scene") {
            el.fail_here("<scene> can only be the root element of a file");
        } else {
            el.fail_here("unknown element <{}>", tag);
        }
    }

    void read_include(const XmlFile& f, const XmlElement& el, int parent, bool in_scene,
                      bool within_emitter) {
        const XmlFile& inc = *includes_.at({&f, el.node().offset_debug()});
        XmlElement root(inc, inc.root(), params_);
        if (root.tag() == "scene") {
            root.expect({"version"}, {"version"});
            check_version(root);
            read_children(inc, inc.root(), parent, in_scene, within_emitter);
        } else if (is_object_tag(root.tag())) {
            check_version(root);  // every file's root carries a version, as in Mitsuba
            read_object(inc, root, std::string(root.tag()), parent, /*file_root=*/true);
        } else {
            root.fail_here("an included file must have <scene> or an object as its root (got <{}>)",
                           root.tag());
        }
    }

    void register_id(const std::string& id, int index, const XmlElement& el) {
        if (id.empty()) el.fail_here("empty id");
        if (reserved_name(id)) el.fail_here("ids starting with '_' are reserved (\"{}\")", id);
        auto [it, inserted] = id_locations_.emplace(id, el.loc());
        if (!inserted) el.fail_here("duplicate id \"{}\" (first defined at {})", id, it->second.str());
        graph_.ids[id] = index;
    }

    void read_object(const XmlFile& f, const XmlElement& el, const std::string& category, int parent,
                     bool file_root = false) {
        if (file_root)
            el.expect({"type", "id", "name", "version"}, {"type", "version"});
        else
            el.expect({"type", "id", "name"}, {"type"});
        const std::string& type = el.get("type");
        if (type.empty()) el.fail_here("<{}> has an empty type", el.tag());
        if (reserved_name(el.get("name"))) el.fail_here("names starting with '_' are reserved");
        int index = int(graph_.nodes.size());
        graph_.nodes.push_back({category, Properties(category, type, el.loc()), {}});
        if (el.has("id")) {
            register_id(el.get("id"), index, el);
            graph_.nodes[size_t(index)].props.set_id(el.get("id"));
        }
        graph_.nodes[size_t(parent)].children.push_back({index, "", el.get("name"), el.loc()});
        read_children(f, el.node(), index, /*in_scene=*/false, /*within_emitter=*/category == "emitter");
    }

    SceneParameters params_;
    FileResolver resolver_;
    std::string main_display_;
    std::map<fs::path, std::unique_ptr<XmlFile>> files_;
    std::vector<std::string>* xml_files_;
    std::vector<std::pair<fs::path, std::string>> include_stack_;
    std::map<std::pair<const XmlFile*, std::ptrdiff_t>, const XmlFile*> includes_;
    std::map<std::string, SourceLocation> id_locations_;
    SceneGraph graph_;
};

}  // namespace

SceneGraph read_scene_graph(const std::string& path, const LoadOptions& options) {
    return Reader(path, options).run();
}

std::string upgrade_scene_file(const std::string& path, const LoadOptions& options) {
    return Reader(path, options).upgrade_main();
}

}  // namespace volguide
