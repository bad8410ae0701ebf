#include "volguide/scene/scene_parameters.h"

#include <cctype>

namespace volguide {

void SceneParameters::declare(const std::string& name, const std::string& value, const SourceLocation& loc) {
    if (name.empty()) fail(loc, "<default> needs a non-empty name");
    for (char c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
            fail(loc, "<default> name '{}' may contain only letters, digits and '_'", name);
    if (declared_.count(name)) return;
    auto o = overrides_.find(name);
    declared_[name] = o != overrides_.end() ? o->second : value;
}

void SceneParameters::check_overrides(const SourceLocation& scene) const {
    for (const auto& [name, value] : overrides_)
        if (!declared_.count(name))
            fail(scene, "-D {}={}: the scene declares no <default name=\"{}\">", name, value, name);
}

std::string SceneParameters::substitute(std::string_view text, const SourceLocation& loc, int depth) const {
    if (text.find('$') == std::string_view::npos) return std::string(text);
    std::string out;
    size_t i = 0;
    while (i < text.size()) {
        char c = text[i];
        if (c == '\\' && i + 1 < text.size() && text[i + 1] == '$') {
            out += '$';
            i += 2;
            continue;
        }
        if (c != '$') {
            out += c;
            ++i;
            continue;
        }
        size_t end = i + 1;
        while (end < text.size() && (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '_'))
            ++end;
        std::string_view candidate = text.substr(i + 1, end - i - 1);
        // Longest declared prefix of the identifier, so "$resx" uses "resx" before "res".
        const std::string* value = nullptr;
        size_t used = 0;
        for (size_t len = candidate.size(); len > 0 && !value; --len) {
            auto it = declared_.find(std::string(candidate.substr(0, len)));
            if (it != declared_.end()) {
                value = &it->second;
                used = len;
            }
        }
        if (!value) {
            if (candidate.empty())
                fail(loc, "stray '$' in \"{}\" (write \\$ for a literal dollar sign)", text);
            fail(loc, "undefined parameter ${} (no <default name=\"{}\"> and no -D)", candidate, candidate);
        }
        // A default may itself refer to other parameters; a bounded depth catches self-reference.
        if (value->find('$') != std::string::npos) {
            if (depth >= 16)
                fail(loc, "parameter ${} refers to itself (through its <default> values)", candidate);
            out += substitute(*value, loc, depth + 1);
        } else {
            out += *value;
        }
        i += 1 + used;
    }
    return out;
}

}  // namespace volguide
