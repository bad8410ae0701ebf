#pragma once
// A part of a distributed render (docs/distributed.md): the image of some sample indices of every
// pixel, written as an EXR that `volguide merge` can combine with the other parts of the same
// render. Every EXR `volguide render` writes is a part (a whole render is the part 0:spp).
//
// Channels: R, G, B the mean sum(w L) / sum(w) as every viewer shows it; W the per-pixel filter
// weight sum(w), so that merged means are sum_i W_i mean_i / sum_i W_i, the single-process value
// (with a box filter W is the sample count); with a variance, variance.R/G/B the per-sample
// variance sum(w L^2) / sum(w) - mean^2. String attributes (volguide.*): scene and field
// fingerprints, scene file, seed, integrator configuration and the sample ranges held.
#include <cstdint>
#include <string>
#include <vector>

#include "volguide/core/image.h"
#include "volguide/render/sample_ranges.h"

namespace volguide {

// What must be equal for two parts to belong to one render.
struct PartInfo {
    std::string scene;       // scene_fingerprint()
    std::string scene_file;  // for messages
    uint64_t seed = 0;
    std::string field;       // prepass_fingerprint(), "none" for an integrator without a pre-pass
    std::string integrator;  // Integrator::configuration()
    SampleRanges samples;    // normalized
};

struct RenderPart {
    Image mean;
    Image variance;              // empty: none
    std::vector<double> weight;  // sum(w) per pixel
    PartInfo info;
};

// Throws InputError naming the file.
void write_part(const std::string& path, const RenderPart& part);
// Throws InputError naming the file, also when it is an EXR without a part's metadata.
RenderPart read_part(const std::string& path);

}  // namespace volguide
