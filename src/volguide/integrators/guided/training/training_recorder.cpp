#include "volguide/integrators/guided/training/training_recorder.h"

namespace volguide {

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
        if (!weight.is_finite()) weight = Color3(0.f);
        out[first + j] = {v.x, v.w, weight, 1.f};
    }
    out.insert(out.end(), nee_.begin(), nee_.end());
    clear();
}

}  // namespace volguide
