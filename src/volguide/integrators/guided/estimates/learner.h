#pragma once
// guided_volpath's learner between passes: each thread's CellRecorder (cell_recorder.h) and cell
// statistics of the current pass, the sums of the passes so far and the film's pixel moments. The
// allocation (allocation.h) learns from it over the render's own passes (or a saved pre-pass's learning
// passes, learning_pass.h); rrs=ears (continuation_snapshot.h) runs one over the render's passes too.
// end_pass() (between passes: no walk runs) adds the threads' sums to the total: integer sums, so the
// total is the same for any thread count.
#include <tbb/enumerable_thread_specific.h>

#include "volguide/integrators/guided/estimates/cell_recorder.h"
#include "volguide/integrators/guided/estimates/cell_statistics.h"
#include "volguide/integrators/guided/estimates/cost_model.h"

namespace volguide {

class Learner {
  public:
    // `cells`: the field's leaves + 1; the film's width and height; the costs the recorders weigh
    // work with (must outlive the learner).
    Learner(size_t cells, int width, int height, const CostModel& costs);
    // The calling thread's recorder (one camera sample at a time: begin ... end).
    CellRecorder& recorder() const { return threads_.local().recorder; }
    long pixel(Point2f film_uv) const { return pixels_.pixel(film_uv); }
    // Adds the threads' statistics of the pass to the total.
    void end_pass();
    const CellStatistics& total() const { return total_; }
    // The total as restored from a checkpoint (its cell count must match).
    void set_total(CellStatistics total);
    // The pixel moments of the passes so far (the current pass's join them in end_pass(), like the
    // statistics: a pass cut short leaves them as they were).
    const PixelMoments& pixels() const { return pixels_total_; }
    // The pixel moments as restored from a checkpoint (PixelMoments::restore).
    void restore_pixels(const std::string& bytes) { pixels_total_.restore(bytes); }

  private:
    struct Thread {
        Thread(size_t cells, PixelMoments* pixels, const CostModel* costs)
            : stats(cells), recorder(stats, *pixels, *costs) {}
        CellStatistics stats;
        CellRecorder recorder;
    };
    PixelMoments pixels_, pixels_total_;  // the current pass's (the recorders add), the passes' so far
    mutable tbb::enumerable_thread_specific<Thread> threads_;
    CellStatistics total_;
};

}  // namespace volguide
