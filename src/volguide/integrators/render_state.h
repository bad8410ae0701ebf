#pragma once
// What a render's later passes need of its earlier ones (`volguide render --checkpoint`, --resume;
// docs/distributed.md, "Checkpoints"): the film's sums, the passes done (the schedule's next pass and
// the samplers' next sample index), the per-sample noise's normaliser the passes report with
// (PassReport::relative_variance, which guided_volpath learns from), the image's counters and the
// integrator's own state (Integrator::render_state). A render resumed from it (RenderOptions::resume)
// renders exactly the passes the interrupted one would have: the same image, bit for bit.
#include <cstdint>
#include <string>
#include <vector>

#include "volguide/render/sensors/film_buffer.h"

namespace volguide {

struct RenderState {
    int passes = 0;             // passes merged into the film
    int spp_done = 0;           // their samples per pixel: the next sample index is first_sample + spp_done
    uint64_t first_sample = 0;  // RenderOptions::first_sample of the render
    FilmSums film;
    std::vector<float> noise_scale;  // empty until the first pass of two or more samples per pixel
    uint64_t samples = 0, nonfinite_samples = 0, discarded_samples = 0;
    std::string integrator;  // Integrator::render_state()
};

// Little-endian bytes (core/bytes.h) and back; deserialize throws std::runtime_error naming the field
// of malformed bytes.
std::string serialize_render_state(const RenderState& state);
RenderState deserialize_render_state(const std::string& bytes);

}  // namespace volguide
