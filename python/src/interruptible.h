#pragma once
// Long jobs (loading, training, rendering) called from Python: the job runs on a worker thread
// with the GIL released, so other Python threads keep running; the calling thread waits in short
// slices and, between them, briefly takes the GIL to let Python run its signal handlers
// (PyErr_CheckSignals). When a handler raises (Ctrl-C: KeyboardInterrupt) the job's cancel flag is
// set, the job stops at its next check (the render loop: the end of the current pass), and the
// Python exception is raised once the worker has finished, so nothing outlives the call.
#include <pybind11/pybind11.h>

#include <atomic>
#include <functional>

namespace volguide::python {

// Runs `job` as described above; rethrows the job's own exception, or the Python exception of an
// interrupt (which wins: the job's result is incomplete then). The GIL must be held on entry.
void run_interruptible(const std::function<void()>& job, std::atomic<bool>& cancel);

}  // namespace volguide::python
