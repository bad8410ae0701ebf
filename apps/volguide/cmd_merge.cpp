// `volguide merge`: the parts of one distributed render (render --samples chunks, merged images)
// into the image of their union (render/merge_parts.h, docs/distributed.md).
#include <fmt/format.h>

#include "cli_util.h"
#include "commands.h"
#include "volguide/core/log.h"
#include "volguide/render/image_io.h"
#include "volguide/render/merge_parts.h"

namespace volguide::cli {

int run_merge(const MergeArgs& args) {
    if (extension_of(args.output) != ".exr")
        throw UsageError(fmt::format("merge output '{}' must end in .exr", args.output));
    std::vector<NamedPart> parts;
    for (const std::string& file : args.parts) parts.push_back({file, read_part(file)});
    const MergeResult result = merge_parts(parts);
    write_part(args.output, result.merged);
    std::string var_output;
    if (!result.merged.variance.pixels.empty()) {
        var_output = variance_path(args.output);
        write_exr(var_output, result.merged.variance);
    }
    const SampleRanges& all = result.merged.info.samples;
    if (!result.gaps.empty())
        warn({}, "samples {} are missing between the parts (a preempted or failed chunk?); the image holds {}",
             format_ranges(result.gaps), format_ranges(all));
    fmt::print("parts: {}\n", parts.size());
    fmt::print("samples: {}\n", format_ranges(all));
    fmt::print("spp: {}\n", total_count(all));
    if (!result.gaps.empty()) fmt::print("gaps: {}\n", format_ranges(result.gaps));
    fmt::print("output: {}\n", args.output);
    if (!var_output.empty()) fmt::print("variance: {}\n", var_output);
    return 0;
}

}  // namespace volguide::cli
