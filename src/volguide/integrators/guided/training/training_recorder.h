#pragma once
// Turns one camera path into guiding-field training samples (docs/theory.md §10.2). The walk (volpath's,
// with the recorder as its PathRecorder, path_recorder.h; the decisions are the policy's, unguided
// or guided) reports, in path order:
//   - every contribution it adds to the pixel estimate (NEE, emitter hits with their MIS weights);
//   - at each real medium scattering vertex x_j, after sampling the next direction w_j with pdf p:
//     the position, w_j and the throughput up to and including f_p / p;
//   - at each medium vertex's NEE: the light's direction and the MIS-weighted radiance over the
//     light sample's pdf (the NEE strategy's own sample of the radiance arriving at x_j).
// finish() then emits, per vertex, the suffix radiance L^(x_j, w_j) = (everything contributed after
// the vertex was recorded) / throughput_j as the sample {x_j, w_j, L^ / p} -- zero-valued samples
// included, they count in the leaf's fluence mean -- and one sample per non-zero NEE with count 0.
//
// Why NEE samples: the walk's emitter hits carry the phase-sampling MIS weight, so the suffix alone
// estimates only that share of the direct light (none at all for point lights, which phase sampling
// never hits). The two strategies' samples at a vertex together are the MIS estimator of the
// incident radiance L(x_j, w) dw: the sum of their weights estimates the fluence, their weighted
// directions the directional distribution -- the same quantity the photon pass trains.
//
// Directions are where the radiance comes from (towards the light, docs/theory.md §1.1): the sampled
// travel direction w_j, exactly the photon samples' -w_travel convention.
//
// Split paths (guided splitting, walk_policy.h's continuation) form a tree: a copy made at a
// continuation decision is walked after the current branch ends, and what it collects belongs to
// the vertices before the split. Each vertex keeps its parent (the last vertex of its branch when
// it was recorded); branch_point() hands a copy the current vertex, resume_branch() makes it
// current again when the copy is walked. L^(x_j, w_j) is then everything contributed in j's
// subtree over j's throughput: the copies' contributions carry their 1/q, so the sum over the n
// copies estimates one continuation. Unsplit paths are chains: the subtree is the suffix.
#include <vector>

#include "volguide/core/color.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/integrators/volpath/path_recorder.h"

namespace volguide {

class TrainingRecorder final : public PathRecorder {
public:
    void clear();
    // A contribution the walk adds to the pixel (after its throughput and MIS weight).
    void record_contribution(const Color3& value) override {
        if (current_ >= 0) suffix_[size_t(current_)] += value;
    }
    // A medium vertex: `pdf` is the density the next direction w was sampled with (phase sampling
    // or a guided mixture) and `throughput` the path weight including f_p / pdf.
    void record_medium_vertex(const Point3f& x, const Vec3f& w, float pdf, const Color3& throughput) override {
        vertices_.push_back({x, w, pdf, throughput, current_});
        suffix_.push_back(Color3(0.f));
        current_ = int(vertices_.size()) - 1;
    }
    int branch_point() override { return current_; }
    void resume_branch(int point) override { current_ = point; }
    // The MIS-weighted NEE radiance estimate at x towards the light d (weight = L T w_mis / p_light).
    void record_medium_nee(const Point3f& x, const Vec3f& d, const Color3& weight) override {
        if (!weight.is_black() && weight.is_finite()) nee_.push_back({x, d, weight, 0.f});
    }
    // Appends the path's samples to `out` (vertices in path order, then NEE samples) and clears.
    void finish(std::vector<RadianceSample>& out);

private:
    struct Vertex {
        Point3f x;
        Vec3f w;
        float pdf;
        Color3 throughput;
        int parent;  // -1: the first vertex of the camera sample
    };
    std::vector<Vertex> vertices_;
    std::vector<Color3> suffix_;  // suffix_[j]: contributions made while j was the current vertex
    int current_ = -1;            // the current branch's last vertex (-1: none yet)
    std::vector<RadianceSample> nee_;
};

}  // namespace volguide
