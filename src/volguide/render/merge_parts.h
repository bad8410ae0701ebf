#pragma once
// Merging the parts of one distributed render (`volguide merge`): checks that they belong together
// (same scene, seed, field and integrator, same size, disjoint sample ranges) and combines them
// weighted by their per-pixel filter weights W (render_part.h): mean = sum_i W_i mean_i / sum_i W_i,
// the single-process image of the union of their samples up to float32 rounding (the parts store
// float32 means and the render loop sums a pass's samples in float before adding passes in double,
// so parts with other pass boundaries round differently: relative differences of order 1e-7,
// relMSE of order 1e-14; docs/distributed.md). Variances merge through their second moments.
#include <string>
#include <vector>

#include "volguide/render/render_part.h"

namespace volguide {

struct NamedPart {
    std::string file;  // for messages
    RenderPart part;
};

struct MergeResult {
    RenderPart merged;    // info.samples = the union
    SampleRanges gaps;    // holes between the parts' ranges (a preempted chunk leaves one)
};

// Throws InputError naming the file that does not belong and why.
MergeResult merge_parts(const std::vector<NamedPart>& parts);

}  // namespace volguide
