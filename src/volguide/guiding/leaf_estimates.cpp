#include "volguide/guiding/leaf_estimates.h"

#include <algorithm>
#include <cmath>

#include "volguide/core/parallel.h"

namespace volguide {

Vec3f octahedral_decode(Point2f uv) {
    float x = 2.f * uv.x - 1.f, y = 2.f * uv.y - 1.f;
    const float z = 1.f - std::abs(x) - std::abs(y);
    if (z < 0.f) {
        const float fx = (1.f - std::abs(y)) * std::copysign(1.f, x),
                    fy = (1.f - std::abs(x)) * std::copysign(1.f, y);
        x = fx;
        y = fy;
    }
    return normalize(Vec3f(x, y, z));
}

uint16_t quantise_texel(float x, float max) {
    return max > 0.f && std::isfinite(x) ? uint16_t(std::lround(std::clamp(x / max, 0.f, 1.f) * 65535.f))
                                         : uint16_t(0);
}

LeafEstimates::LeafEstimates(const GuidingField& field, const InscatterCache& inscatter, int resolution)
    : field_(field), inscatter_(inscatter), resolution_(std::max(resolution, 0)) {
    if (resolution_ == 0) return;
    const int R = resolution_;
    texels_per_table_ = size_t(R * R);
    const std::vector<GuidingLeaf>& leaves = field.leaves();
    headers_.assign(leaves.size(), Header{});
    texels_.assign(leaves.size() * size_t(R * R), EstimateTexel{0, 0});
    parallel_for(size_t(0), leaves.size(), [&](size_t l) {
        const GuidingLeaf& leaf = leaves[l];
        Header& h = headers_[l];
        h.valid = leaf.valid;
        h.fluence = leaf.fluence;
        const float phi = leaf.fluence.average();
        if (!leaf.valid || !(phi > 0.f)) return;
        std::vector<float> inscattered(size_t(R * R)), incident(size_t(R * R));
        float max_i = 0.f, max_l = 0.f;
        for (int v = 0; v < R; ++v)
            for (int u = 0; u < R; ++u) {
                const Vec3f w =
                    octahedral_decode(Point2f((float(u) + 0.5f) / float(R), (float(v) + 0.5f) / float(R)));
                const size_t k = size_t(v * R + u);
                inscattered[k] = inscatter.inscattered(int(l), w).average() / phi;
                incident[k] = GuidingField::incident(leaf, w).average() / phi;
                if (std::isfinite(inscattered[k])) max_i = std::max(max_i, inscattered[k]);
                if (std::isfinite(incident[k])) max_l = std::max(max_l, incident[k]);
            }
        h.scale_inscattered = max_i / 65535.f;
        h.scale_incident = max_l / 65535.f;
        EstimateTexel* t = &texels_[l * size_t(R * R)];
        for (size_t k = 0; k < size_t(R * R); ++k)
            t[k] = {quantise_texel(inscattered[k], max_i), quantise_texel(incident[k], max_l)};
    });
}

bool LeafEstimates::texel_averages(int leaf, float* inscattered, float* incident) const {
    const size_t n = size_t(resolution_ * resolution_);
    std::fill(inscattered, inscattered + n, 0.f);
    std::fill(incident, incident + n, 0.f);
    if (resolution_ == 0 || leaf < 0 || !headers_[size_t(leaf)].valid) return false;
    const Header& h = headers_[size_t(leaf)];
    const float phi = h.fluence.average();
    const EstimateTexel* t = &texels_[size_t(leaf) * n];
    for (size_t k = 0; k < n; ++k) {
        inscattered[k] = phi * h.scale_inscattered * float(t[k].inscattered);
        incident[k] = phi * h.scale_incident * float(t[k].incident);
    }
    return true;
}

bool LeafEstimates::lookup_exact(int leaf, const Direction& d, Color3& inscattered, Color3& incident) const {
    const GuidingLeaf& gl = field_.leaves()[size_t(leaf)];
    if (!gl.valid) return false;
    inscattered = inscatter_.inscattered(leaf, d.w);
    incident = GuidingField::incident(gl, d.w);
    return true;
}

bool LeafEstimates::lookup_average_exact(int leaf, const Direction& d, float& inscattered, float& incident) const {
    Color3 Li, L;
    if (!lookup(leaf, d, Li, L)) return false;
    inscattered = Li.average();
    incident = L.average();
    return true;
}

}  // namespace volguide
