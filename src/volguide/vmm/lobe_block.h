#pragma once
// A mixture's lobes as the render-time decisions read them (docs/theory.md §3.7): float
// structure-of-arrays blocks of the mixture's own lobe count rounded up to kLobeLanes, with what every
// evaluation and sample needs precomputed — the scale w c~(kappa) (weight times normalisation) and
// expm1(-2 kappa) (the lobe's sampling constant) — so that a decision loads the lobes and computes
// nothing per lobe but the direction-dependent part. Pad lanes carry weight and scale 0: they never
// add mass and are never sampled. `LobeStore` keeps every leaf's block in one 64-byte-aligned
// allocation: an 8-lobe leaf is 224 bytes (256 with its alignment: 4 cache lines) where a
// VmfMixture<32> is 772.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "volguide/vmm/vmm.h"

namespace volguide {

// Lanes a block is padded to: the widest float vector the kernels use (vmf_simd.h).
inline constexpr int kLobeLanes = 8;

// The arrays of one block, each `padded` floats, in this order.
enum class LobeArray : int { MuX, MuY, MuZ, Kappa, Scale, Expm1, Weight, Count };
inline constexpr int kLobeArrays = int(LobeArray::Count);

// A read-only view of one mixture's block (contiguous: kLobeArrays x padded floats).
struct LobeBlock {
    const float* data = nullptr;
    int count = 0;   // lobes (0: an empty mixture)
    int padded = 0;  // count rounded up to kLobeLanes
    const float* array(LobeArray a) const { return data + size_t(a) * size_t(padded); }
    const float* mu_x() const { return array(LobeArray::MuX); }
    const float* mu_y() const { return array(LobeArray::MuY); }
    const float* mu_z() const { return array(LobeArray::MuZ); }
    const float* kappa() const { return array(LobeArray::Kappa); }
    const float* scale() const { return array(LobeArray::Scale); }    // weight x c~(kappa)
    const float* expm1() const { return array(LobeArray::Expm1); }    // expm1(-2 kappa)
    const float* weight() const { return array(LobeArray::Weight); }  // sums to 1
    bool empty() const { return count == 0; }
};

// Floats a block of `count` lobes takes.
inline size_t lobe_block_floats(int count) {
    const int padded = (count + kLobeLanes - 1) / kLobeLanes * kLobeLanes;
    return size_t(kLobeArrays) * size_t(padded);
}

// Writes `m`'s block into `out` (lobe_block_floats(m.count) floats) and returns its view.
template <int N>
LobeBlock write_lobe_block(const VmfMixture<N>& m, float* out);

// One block per leaf in one aligned allocation (the direction decisions' copy of the field's
// mixtures: one per field, shared by every decision).
class LobeStore {
  public:
    LobeStore() = default;
    // Blocks of `mixtures[i]` where valid[i], empty blocks elsewhere.
    LobeStore(std::span<const Vmm* const> mixtures, std::span<const uint8_t> valid);

    // Leaf i's block (empty: the leaf has no usable mixture).
    LobeBlock block(int i) const {
        const Entry& e = entries_[size_t(i)];
        return LobeBlock{floats_.get() + e.offset, e.count, e.padded};
    }
    // Hints the cache that leaf i's block will be read soon (its cache lines; nothing for an empty one).
    void prefetch(int i) const {
        const Entry& e = entries_[size_t(i)];
        const char* p = reinterpret_cast<const char*>(floats_.get() + e.offset);
        for (size_t b = 0; b < size_t(e.count ? lobe_block_floats(e.count) : 0) * sizeof(float); b += 64)
            __builtin_prefetch(p + b);
    }
    size_t size() const { return entries_.size(); }
    // Bytes held (the blocks and their index).
    size_t bytes() const { return floats_size_ * sizeof(float) + entries_.size() * sizeof(Entry); }

  private:
    struct Entry {
        uint32_t offset = 0;
        uint16_t count = 0, padded = 0;
    };
    struct AlignedDelete {
        void operator()(float* p) const;
    };
    std::vector<Entry> entries_;
    std::unique_ptr<float[], AlignedDelete> floats_;
    size_t floats_size_ = 0;
};

// Sampling one lobe with its precomputed expm1(-2 kappa) (vmf.h's VmfLobe::sample without its
// exponential).
Vec3f sample_vmf_prepared(const Vec3f& mu, float kappa, float expm1_2k, Point2f u);

template <int N>
LobeBlock write_lobe_block(const VmfMixture<N>& m, float* out) {
    LobeBlock b{out, m.count, (m.count + kLobeLanes - 1) / kLobeLanes * kLobeLanes};
    float* a[kLobeArrays];
    for (int i = 0; i < kLobeArrays; ++i) a[i] = out + size_t(i) * size_t(b.padded);
    for (int k = 0; k < b.padded; ++k) {
        const bool real = k < m.count;
        a[int(LobeArray::MuX)][k] = real ? m.mu_x[k] : 0.f;
        a[int(LobeArray::MuY)][k] = real ? m.mu_y[k] : 0.f;
        a[int(LobeArray::MuZ)][k] = real ? m.mu_z[k] : 1.f;
        a[int(LobeArray::Kappa)][k] = real ? m.kappa[k] : 0.f;
        a[int(LobeArray::Scale)][k] = real ? m.weight[k] * m.norm[k] : 0.f;
        a[int(LobeArray::Expm1)][k] = real ? float(std::expm1(-2.0 * double(m.kappa[k]))) : 0.f;
        a[int(LobeArray::Weight)][k] = real ? m.weight[k] : 0.f;
    }
    return b;
}

}  // namespace volguide
