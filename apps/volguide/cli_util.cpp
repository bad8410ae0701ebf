#include "cli_util.h"

#include <algorithm>
#include <filesystem>

#include "commands.h"

namespace volguide::cli {

std::map<std::string, std::string> parse_defines(const std::vector<std::string>& defines) {
    std::map<std::string, std::string> out;
    for (const std::string& d : defines) {
        size_t eq = d.find('=');
        if (eq == std::string::npos || eq == 0) throw UsageError("-D expects name=value, got '" + d + "'");
        std::string name = d.substr(0, eq);
        if (!out.emplace(name, d.substr(eq + 1)).second) throw UsageError("-D " + name + " is given twice");
    }
    return out;
}

std::string extension_of(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

std::string default_output(const std::string& scene) {
    return std::filesystem::path(scene).stem().string() + ".exr";
}

std::string variance_path(const std::string& output) {
    std::filesystem::path p(output);
    std::filesystem::path name = p.stem().string() + "_var.exr";
    return (p.parent_path() / name).string();
}

}  // namespace volguide::cli
