#pragma once
// The render loop of light tracers (Integrator::traces_from_emitters, ptracer): one light path per
// (film pixel, sample index) — W·H·spp paths, as Mitsuba 3's adjoint render — each drawing from
// Sampler(seed, pixel, sample), the same streams a camera sample of that pixel would. The paths'
// splats are kept per 16 x 16 tile and added to the film tile by tile in a fixed order, a wave of
// tiles at a time, so the image is bit-identical for any thread count. The film holds the splats'
// sum (each spread by the reconstruction filter normalised over the pixels it reaches, Mitsuba's
// normalised image block); the image is that sum over the samples per pixel done. Passes, time budget,
// cancellation, --samples FIRST:COUNT and progress as render_loop.h: a stopped pass is dropped whole.
#include <tbb/task_arena.h>

#include <chrono>

#include "volguide/integrators/render_loop.h"

namespace volguide {

// Called by render() for an integrator that traces_from_emitters(). Throws std::invalid_argument when
// the sensor cannot be connected to (not a pinhole) or a variance image is asked for.
RenderResult render_light_tracing(const Scene& scene, const Integrator& integrator,
                                  const RenderOptions& options, tbb::task_arena& arena,
                                  std::chrono::steady_clock::time_point job_start);

}  // namespace volguide
