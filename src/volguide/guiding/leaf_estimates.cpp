#include "volguide/guiding/leaf_estimates.h"

#include <algorithm>
#include <cmath>

#include "volguide/core/parallel.h"

namespace volguide {

Point2f octahedral_encode(const Vec3f& w) {
    const float l1 = std::abs(w.x) + std::abs(w.y) + std::abs(w.z);
    float x = w.x / l1, y = w.y / l1;
    if (w.z < 0.f) {
        const float fx = (1.f - std::abs(y)) * std::copysign(1.f, x),
                    fy = (1.f - std::abs(x)) * std::copysign(1.f, y);
        x = fx;
        y = fy;
    }
    return Point2f(0.5f * x + 0.5f, 0.5f * y + 0.5f);
}

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

LeafEstimates::Direction LeafEstimates::prepare(const Vec3f& w) const {
    Direction d;
    d.w = w;
    if (resolution_ == 0) return d;
    // Bilinear between the four nearest texel centres (clamped at the map's edges).
    const int R = resolution_;
    const Point2f uv = octahedral_encode(w);
    const float x = std::clamp(uv.x * float(R) - 0.5f, 0.f, float(R - 1));
    const float y = std::clamp(uv.y * float(R) - 0.5f, 0.f, float(R - 1));
    const int x0 = std::min(int(x), std::max(R - 2, 0)), y0 = std::min(int(y), std::max(R - 2, 0));
    const int x1 = std::min(x0 + 1, R - 1), y1 = std::min(y0 + 1, R - 1);
    const float fx = x - float(x0), fy = y - float(y0);
    d.offset[0] = y0 * R + x0;
    d.offset[1] = y0 * R + x1;
    d.offset[2] = y1 * R + x0;
    d.offset[3] = y1 * R + x1;
    d.weight[0] = (1.f - fx) * (1.f - fy);
    d.weight[1] = fx * (1.f - fy);
    d.weight[2] = (1.f - fx) * fy;
    d.weight[3] = fx * fy;
    return d;
}

void LeafEstimates::prefetch(int leaf, const Direction& d) const {
    if (leaf < 0 || resolution_ == 0) return;
    __builtin_prefetch(&headers_[size_t(leaf)]);
    d.prefetch(&texels_[size_t(leaf) * size_t(resolution_ * resolution_)]);
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

bool LeafEstimates::lookup(int leaf, const Direction& d, Color3& inscattered, Color3& incident) const {
    if (leaf < 0) return false;
    if (resolution_ == 0) {
        const GuidingLeaf& gl = field_.leaves()[size_t(leaf)];
        if (!gl.valid) return false;
        inscattered = inscatter_.inscattered(leaf, d.w);
        incident = GuidingField::incident(gl, d.w);
        return true;
    }
    const Header& h = headers_[size_t(leaf)];
    if (!h.valid) return false;
    float inscattered_texel, incident_texel;
    d.interpolate(&texels_[size_t(leaf) * size_t(resolution_ * resolution_)], inscattered_texel, incident_texel);
    inscattered = h.fluence * (h.scale_inscattered * inscattered_texel);
    incident = h.fluence * (h.scale_incident * incident_texel);
    return true;
}

}  // namespace volguide
