#include "volguide/vmm/lobe_block.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <new>
#include <stdexcept>

#include "volguide/core/frame.h"

namespace volguide {

void LobeStore::AlignedDelete::operator()(float* p) const { std::free(p); }

LobeStore::LobeStore(std::span<const Vmm* const> mixtures, std::span<const uint8_t> valid)
    : entries_(mixtures.size()) {
    size_t total = 0;
    for (size_t i = 0; i < mixtures.size(); ++i)
        if (valid[i] && mixtures[i]->count > 0) total += lobe_block_floats(mixtures[i]->count);
    if (total >= (size_t(1) << 32)) throw std::length_error("LobeStore: more than 2^32 floats of lobes");
    // 64-byte blocks: every block starts a cache line (a multiple of kLobeLanes floats = 32 bytes,
    // rounded to 64 by the allocation of each block below).
    size_t offset = 0;
    for (size_t i = 0; i < mixtures.size(); ++i) {
        if (!(valid[i] && mixtures[i]->count > 0)) continue;
        entries_[i].offset = uint32_t(offset);
        offset += (lobe_block_floats(mixtures[i]->count) + 15) / 16 * 16;
    }
    floats_size_ = std::max<size_t>(offset, 16);
    float* p = static_cast<float*>(std::aligned_alloc(64, floats_size_ * sizeof(float)));
    if (!p) throw std::bad_alloc();
    floats_.reset(p);
    for (size_t i = 0; i < mixtures.size(); ++i) {
        if (!(valid[i] && mixtures[i]->count > 0)) continue;
        const LobeBlock b = write_lobe_block(*mixtures[i], floats_.get() + entries_[i].offset);
        entries_[i].count = uint16_t(b.count);
        entries_[i].padded = uint16_t(b.padded);
    }
}

Vec3f sample_vmf_prepared(const Vec3f& mu, float kappa, float expm1_2k, Point2f u) {
    // 1 - cos = -log1p(u expm1(-2 kappa)) / kappa (vmf.cpp's vmf_sample_one_minus_cos).
    const float t = kappa < kVmfUniformKappa ? 2.f * u.x : std::clamp(-std::log1p(u.x * expm1_2k) / kappa, 0.f, 2.f);
    const float sin_theta = std::sqrt(std::max(t * (2.f - t), 0.f));
    const float phi = 2.f * Pi * u.y;
    const Vec3f local(sin_theta * std::cos(phi), sin_theta * std::sin(phi), 1.f - t);
    return Frame(mu).to_world(local);
}

}  // namespace volguide
