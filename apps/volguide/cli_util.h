#pragma once
// Small helpers shared by the commands.
#include <map>
#include <string>
#include <vector>

namespace volguide::cli {

// "name=value" strings → map; throws UsageError for a malformed or repeated entry.
std::map<std::string, std::string> parse_defines(const std::vector<std::string>& defines);
// Lower-case extension including the dot ("" when none).
std::string extension_of(const std::string& path);
// <scene stem>.exr in the current directory.
std::string default_output(const std::string& scene);
// "dir/out.exr" → "dir/out_var.exr".
std::string variance_path(const std::string& output);

}  // namespace volguide::cli
