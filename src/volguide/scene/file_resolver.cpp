#include "volguide/scene/file_resolver.h"

namespace volguide {

namespace fs = std::filesystem;

std::string FileResolver::join_display(const std::string& dir, const std::string& name) {
    if (dir.empty() || fs::path(name).is_absolute()) return fs::path(name).lexically_normal().string();
    return (fs::path(dir) / name).lexically_normal().string();
}

std::optional<ResolvedFile> FileResolver::resolve(const std::string& name, const Dir& current,
                                                  bool want_directory) const {
    auto usable = [&](const fs::path& p) {
        std::error_code ec;
        return want_directory ? fs::is_directory(p, ec) : fs::is_regular_file(p, ec);
    };
    fs::path p(name);
    if (name.empty()) return std::nullopt;
    if (p.is_absolute()) {
        if (usable(p)) return ResolvedFile{p.lexically_normal(), p.lexically_normal().string()};
        return std::nullopt;
    }
    auto try_dir = [&](const Dir& d) -> std::optional<ResolvedFile> {
        fs::path candidate = fs::absolute(d.real / p).lexically_normal();
        if (usable(candidate)) return ResolvedFile{candidate, join_display(d.display, name)};
        return std::nullopt;
    };
    if (auto r = try_dir(current)) return r;
    for (const Dir& d : search_)
        if (auto r = try_dir(d)) return r;
    return try_dir(main_);
}

}  // namespace volguide
