#pragma once
// Progress reports from long library operations (training, rendering) to the application, which
// decides how to show them. The library never prints progress itself.
#include <functional>
#include <string>

namespace volguide {

struct Progress {
    std::string phase;     // "preprocess", "rendering", ...
    double fraction = 0;   // estimated share of the whole job done, in [0, 1]
    int spp_done = 0;      // samples per pixel completed (whole passes)
    int spp_target = 0;    // 0 when only a time budget bounds the render
    double elapsed = 0;    // seconds since the job started
    double eta = -1;       // estimated seconds left; < 0 when unknown
};

// May be called from worker threads, but never concurrently.
using ProgressCallback = std::function<void(const Progress&)>;

}  // namespace volguide
