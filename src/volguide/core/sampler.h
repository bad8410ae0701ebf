#pragma once
// Counter-based random numbers: every value is a pure function of
// (seed, pixel, sample index, dimension). Nothing depends on which thread runs which tile,
// so a seed gives a bit-identical image for any thread count, and any sample can be replayed.
#include <cstdint>

#include "volguide/core/math.h"
#include "volguide/core/vec.h"

namespace volguide {

// 64-bit finaliser (splitmix64 / Stafford variant 13): a bijection with full avalanche.
constexpr uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}
constexpr uint64_t hash_combine(uint64_t h, uint64_t v) { return mix64(h ^ (v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2))); }

class Sampler {
public:
    Sampler() = default;
    // Starts the stream of one (pixel, sample) pair; `stream` separates independent uses
    // (camera paths = 0; later: training passes, split copies, photons).
    Sampler(uint64_t seed, uint64_t pixel_index, uint64_t sample_index, uint64_t stream = 0) {
        key_ = hash_combine(hash_combine(hash_combine(mix64(seed), pixel_index), sample_index), stream);
        dimension_ = 0;
    }
    // A new independent stream derived from this one (e.g. one per split copy).
    Sampler fork(uint64_t child) const {
        Sampler s;
        s.key_ = hash_combine(hash_combine(key_, 0x5851f42d4c957f2dULL + dimension_), child);
        return s;
    }
    float next_1d() {
        uint64_t bits = mix64(key_ + 0x9e3779b97f4a7c15ULL * (++dimension_));
        return float(bits >> 40) * 0x1p-24f;  // 24 random mantissa bits: in [0, 1)
    }
    Vec2f next_2d() {
        float a = next_1d();
        return {a, next_1d()};
    }
    uint64_t dimension() const { return dimension_; }
    // The stream's identity (a hash of seed, pixel, sample and stream; drawing does not change it):
    // a thread-independent order for what samples rendered in parallel record (online learning).
    uint64_t key() const { return key_; }

private:
    uint64_t key_ = 0;
    uint64_t dimension_ = 0;
};

}  // namespace volguide
