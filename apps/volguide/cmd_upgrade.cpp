// `volguide upgrade IN.xml -o OUT.xml`: a Mitsuba 0.x scene file written in Mitsuba 3's form, which both
// volguide and Mitsuba 3 read (src/volguide/scene/legacy_upgrade.h; docs/scene-format.md, "Mitsuba 0.6
// scenes"). Comments and indentation are kept; errors and warnings name IN's lines.
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "cli_util.h"
#include "commands.h"
#include "volguide/core/atomic_write.h"
#include "volguide/core/log.h"
#include "volguide/scene/loader.h"
#include "volguide/scene/xml_reader.h"

namespace volguide::cli {

namespace {

namespace fs = std::filesystem;

void check_paths(const UpgradeArgs& args) {
    if (extension_of(args.output) != ".xml")
        throw UsageError(fmt::format("output '{}' must end in .xml", args.output));
    std::error_code ec;
    if (fs::exists(args.output, ec) && fs::equivalent(args.scene, args.output, ec))
        throw UsageError("the output must not be the input: keep the Mitsuba 0.x original");
    const fs::path dir = fs::path(args.output).parent_path();
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw FileError(args.output, fmt::format("directory '{}' does not exist", dir.string()));
}

}  // namespace

int run_upgrade(const UpgradeArgs& args) {
    check_paths(args);
    LoadOptions load;
    load.defines = parse_defines(args.defines);
    const std::string text = upgrade_scene_file(args.scene, load);
    const fs::path in_dir = fs::absolute(args.scene).parent_path(), out_dir = fs::absolute(args.output).parent_path();
    if (in_dir.lexically_normal() != out_dir.lexically_normal())
        warn({}, "'{}' is written to another directory than '{}': its relative file names (meshes, textures, "
                 "includes) are kept as written",
             args.output, args.scene);
    const std::string error = write_atomically(args.output, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        out.close();
        if (!out) throw std::runtime_error("write failed");
    });
    if (!error.empty()) throw FileError(args.output, "cannot write the upgraded scene: " + error);
    fmt::print("output: {}\n", args.output);
    return 0;
}

}  // namespace volguide::cli
