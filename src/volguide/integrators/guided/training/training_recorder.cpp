#include "volguide/integrators/guided/training/training_recorder.h"

#include <cmath>
#include <limits>

namespace volguide {

namespace {

// The vertex's second-moment contribution L^2 / p for the variance-aware target (docs/theory.md §23.3):
// the channel mean of the squares, as the image error adds channels; 0 where it is not finite.
float second_moment(const Color3& L, float pdf) {
    if (!(pdf > 0.f)) return 0.f;
    const double m = (double(L[0]) * L[0] + double(L[1]) * L[1] + double(L[2]) * L[2]) / (3.0 * double(pdf));
    return std::isfinite(m) && m < double(std::numeric_limits<float>::max()) ? float(m) : 0.f;
}

}  // namespace

void TrainingRecorder::clear() {
    vertices_.clear();
    suffix_.clear();
    nee_.clear();
    current_ = -1;
}

void TrainingRecorder::finish(std::vector<RadianceSample>& out) {
    // suffix_[j] holds what was added while j was the current vertex; everything in j's subtree is
    // suffix_[j] plus its children's subtrees. A child is recorded after its parent, so one pass
    // backwards adds each finished subtree to its parent: O(vertices).
    const size_t first = out.size();
    out.resize(first + vertices_.size());
    for (size_t j = vertices_.size(); j-- > 0;) {
        const Color3 after = suffix_[j];
        const Vertex& v = vertices_[j];
        if (v.parent >= 0) suffix_[size_t(v.parent)] += after;
        Color3 L;  // L^(x_j, w_j); a zero throughput channel carries no radiance
        for (int c = 0; c < 3; ++c) L[c] = v.throughput[c] > 0.f ? after[c] / v.throughput[c] : 0.f;
        Color3 weight = v.pdf > 0.f ? L * (1.f / v.pdf) : Color3(0.f);
        // A non-finite value would poison the leaf's fluence; keep the vertex as a zero sample.
        const bool finite = weight.is_finite();
        if (!finite) weight = Color3(0.f);
        out[first + j] = {v.x, v.w, weight, 1.f};
        out[first + j].second_moment = finite ? second_moment(L, v.pdf) : 0.f;
    }
    out.insert(out.end(), nee_.begin(), nee_.end());
    clear();
}

}  // namespace volguide
