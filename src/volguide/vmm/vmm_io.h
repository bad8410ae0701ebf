#pragma once
// Binary, versioned serialization of a vMF mixture (for saving/loading the guiding field).
//
// Record layout (all little-endian):
//   8 bytes  magic "VGVMM\0\0\0"
//   u32      format version (kVmmFormatVersion)
//   u32      lobe count K
//   K x 5 f32 per lobe: weight, mu.x, mu.y, mu.z, kappa   (c~(kappa) is recomputed on read)
//   u32      FNV-1a checksum of the version, count and lobe bytes
// Reading validates everything (magic, version, count <= capacity, checksum, finite values,
// weights >= 0 summing to 1, unit axes, kappa range) and throws VmmFormatError on any problem;
// a corrupt, truncated or foreign stream never crashes or yields a bad mixture. Writing checks
// the same conditions (only normalised mixtures are written).
#include <istream>
#include <ostream>
#include <stdexcept>
#include <vector>

#include "volguide/vmm/vmm.h"

namespace volguide {

inline constexpr uint32_t kVmmFormatVersion = 1;

class VmmFormatError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// Lobes as (weight, mu.x, mu.y, mu.z, kappa) tuples; the templates below pack/unpack mixtures.
void write_vmm_record(std::ostream& out, const std::vector<float>& lobes);
std::vector<float> read_vmm_record(std::istream& in, int capacity);

template <int N>
void write_vmm(std::ostream& out, const VmfMixture<N>& m) {
    std::vector<float> lobes;
    lobes.reserve(size_t(m.count) * 5);
    for (int k = 0; k < m.count; ++k)
        for (float v : {m.weight[k], m.mu_x[k], m.mu_y[k], m.mu_z[k], m.kappa[k]}) lobes.push_back(v);
    write_vmm_record(out, lobes);
}

template <int N>
VmfMixture<N> read_vmm(std::istream& in) {
    std::vector<float> lobes = read_vmm_record(in, N);
    VmfMixture<N> m;
    for (size_t i = 0; i < lobes.size(); i += 5)
        m.add_lobe(lobes[i], VmfLobe(Vec3f(lobes[i + 1], lobes[i + 2], lobes[i + 3]), lobes[i + 4]));
    return m;
}

}  // namespace volguide
