#pragma once
// What the guided distance decisions read in each kd leaf a ray crosses, for its direction w:
// L~_i(w) (in-scattered, InscatterCache) and L~(w) (incident, looking ahead along the ray).
//
// Exact, both are sums of exponentials (K x J and K lobes): with fine leaves, a large share of a
// guided render (bench/RESULTS.md (issue 35)): a ray crosses many leaves per decision. Tabulated, each leaf
// keeps an octahedral map of resolution R x R of the two (unit-fluence) shapes, sampled at texel
// centres once after training (16-bit, relative to the leaf's maximum), and a query is one bilinear
// lookup times the leaf's fluence.
// The tables are an approximation of the estimates, so they only shape the distance sampler's
// probabilities: the sampler's pdf is computed from the same values it sampled with, and the
// weights use the true coefficients (docs/theory.md §7.5) — unbiased at any resolution.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "volguide/core/color.h"
#include "volguide/core/vec.h"
#include "volguide/guiding/guiding_field.h"
#include "volguide/guiding/inscatter_cache.h"

namespace volguide {

// One texel of the 16-bit estimate tables (the leaves' here, the regions' in leaf_groups.h):
// L~_i and L~ relative to the table's maxima.
struct EstimateTexel {
    uint16_t inscattered, incident;
};

class LeafEstimates {
  public:
    // resolution 0: exact evaluation. Both must outlive this object.
    LeafEstimates(const GuidingField& field, const InscatterCache& inscatter, int resolution);

    // Where a direction falls in the tables: the same for every leaf, so a ray computes it once
    // and reuses it in each leaf it crosses.
    struct Direction {
        Vec3f w;
        int offset[4] = {0, 0, 0, 0};  // texel indices within a leaf's table
        float weight[4] = {0.f, 0.f, 0.f, 0.f};

        // The bilinear read of one table at this direction, in texel units (times the table's scales).
        void interpolate(const EstimateTexel* table, float& inscattered, float& incident) const {
            inscattered = incident = 0.f;
            for (int k = 0; k < 4; ++k) {
                const EstimateTexel& e = table[offset[k]];
                inscattered += weight[k] * float(e.inscattered);
                incident += weight[k] * float(e.incident);
            }
        }
        // Hints the cache that `table` will be read at this direction soon.
        void prefetch(const EstimateTexel* table) const {
            __builtin_prefetch(table + offset[0]);
            __builtin_prefetch(table + offset[2]);
        }
    };
    Direction prepare(const Vec3f& w) const;  // inline, below

    // L~_i(w) and L~(w) of a leaf; false (and nothing written) for an invalid leaf.
    bool lookup(int leaf, const Direction& d, Color3& inscattered, Color3& incident) const {
        if (leaf < 0) return false;
        if (resolution_ == 0) return lookup_exact(leaf, d, inscattered, incident);
        const Header& h = headers_[size_t(leaf)];
        if (!h.valid) return false;
        float inscattered_texel, incident_texel;
        d.interpolate(&texels_[size_t(leaf) * texels_per_table_], inscattered_texel, incident_texel);
        inscattered = h.fluence * (h.scale_inscattered * inscattered_texel);
        incident = h.fluence * (h.scale_incident * incident_texel);
        return true;
    }
    // Their channel averages (what a distance bin reads, docs/theory.md §7.8): lookup's values averaged,
    // inline for the bins' walk (one per leaf crossed).
    bool lookup_average(int leaf, const Direction& d, float& inscattered, float& incident) const {
        if (leaf < 0) return false;
        if (resolution_ == 0) return lookup_average_exact(leaf, d, inscattered, incident);
        const Header& h = headers_[size_t(leaf)];
        if (!h.valid) return false;
        float inscattered_texel, incident_texel;
        d.interpolate(&texels_[size_t(leaf) * texels_per_table_], inscattered_texel, incident_texel);
        inscattered = (h.fluence * (h.scale_inscattered * inscattered_texel)).average();
        incident = (h.fluence * (h.scale_incident * incident_texel)).average();
        return true;
    }
    bool lookup(int leaf, const Vec3f& w, Color3& inscattered, Color3& incident) const {
        return lookup(leaf, prepare(w), inscattered, incident);
    }
    // Channel averages of L~_i and L~ of `leaf` at each texel centre (resolution^2 values each, as
    // lookups read them); false (zeros written) for an invalid leaf or without tables.
    bool texel_averages(int leaf, float* inscattered, float* incident) const;
    // Hints the cache that `leaf` will be looked up soon.
    void prefetch(int leaf, const Direction& d) const {
        if (leaf < 0 || resolution_ == 0) return;
        __builtin_prefetch(&headers_[size_t(leaf)]);
        d.prefetch(&texels_[size_t(leaf) * texels_per_table_]);
    }

    int resolution() const { return resolution_; }
    size_t memory_bytes() const {
        return headers_.capacity() * sizeof(Header) + texels_.capacity() * sizeof(EstimateTexel);
    }

  private:
    // Compact, because the lookups miss the cache (a ray visits ~10 random leaves): what a lookup
    // reads of a leaf is its header and 4 texels, and 2000 leaves at R = 16 fit in 2 MB.
    struct Header {
        Color3 fluence;
        float scale_inscattered = 0.f, scale_incident = 0.f;  // value = scale * texel / 65535
        bool valid = false;
    };
    // lookup and lookup_average without tables (resolution 0): the leaf's VMMs evaluated.
    bool lookup_exact(int leaf, const Direction& d, Color3& inscattered, Color3& incident) const;
    bool lookup_average_exact(int leaf, const Direction& d, float& inscattered, float& incident) const;

    const GuidingField& field_;
    const InscatterCache& inscatter_;
    int resolution_;
    size_t texels_per_table_ = 0;  // resolution^2
    std::vector<Header> headers_;
    std::vector<EstimateTexel> texels_;  // leaf l: [l * R * R, (l + 1) * R * R), row-major over (u, v)
};

// x / max as a 16-bit texel (0 for a non-finite x or a table whose maximum is not positive).
uint16_t quantise_texel(float x, float max);

// The octahedral map of the unit sphere onto [0, 1]^2 (continuous, area-distorting) and its inverse.
inline Point2f octahedral_encode(const Vec3f& w) {
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
Vec3f octahedral_decode(Point2f uv);

inline LeafEstimates::Direction LeafEstimates::prepare(const Vec3f& w) const {
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

}  // namespace volguide
