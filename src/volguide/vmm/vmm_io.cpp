#include "volguide/vmm/vmm_io.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

namespace volguide {

namespace {
constexpr std::array<char, 8> kMagic{'V', 'G', 'V', 'M', 'M', 0, 0, 0};
// Largest kappa accepted on read: fits stop at 32000, products of two such lobes reach 64000.
constexpr float kMaxStoredKappa = 1e7f;

void put_u32(std::vector<unsigned char>& buf, uint32_t v) {
    for (int i = 0; i < 4; ++i) buf.push_back((unsigned char)(v >> (8 * i)));
}
uint32_t get_u32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
uint32_t fnv1a(const unsigned char* p, size_t n) {
    uint32_t h = 2166136261u;
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 16777619u;
    return h;
}
void read_exact(std::istream& in, unsigned char* dst, size_t n, const char* what) {
    in.read(reinterpret_cast<char*>(dst), std::streamsize(n));
    if (size_t(in.gcount()) != n) throw VmmFormatError(std::string("VMM record truncated in ") + what);
}
// Throws unless the lobes form a valid normalised mixture.
void validate(const std::vector<float>& lobes) {
    const size_t count = lobes.size() / 5;
    if (lobes.size() % 5 != 0) throw VmmFormatError("VMM lobe data is not a multiple of 5 floats");
    double weight_sum = 0.0;
    for (size_t k = 0; k < count; ++k) {
        const float* l = &lobes[5 * k];
        for (int i = 0; i < 5; ++i)
            if (!std::isfinite(l[i]))
                throw VmmFormatError("VMM lobe " + std::to_string(k) + " has a non-finite value");
        if (l[0] < 0.f) throw VmmFormatError("VMM lobe " + std::to_string(k) + " has a negative weight");
        double len = std::sqrt(double(l[1]) * l[1] + double(l[2]) * l[2] + double(l[3]) * l[3]);
        if (std::abs(len - 1.0) > 1e-4)
            throw VmmFormatError("VMM lobe " + std::to_string(k) + " axis is not unit length");
        if (l[4] < 0.f || l[4] > kMaxStoredKappa)
            throw VmmFormatError("VMM lobe " + std::to_string(k) + " kappa out of range");
        weight_sum += l[0];
    }
    if (count > 0 && std::abs(weight_sum - 1.0) > 1e-4) throw VmmFormatError("VMM weights do not sum to 1");
}

}  // namespace

void write_vmm_record(std::ostream& out, const std::vector<float>& lobes) {
    validate(lobes);  // never write what read would reject
    std::vector<unsigned char> body;
    put_u32(body, kVmmFormatVersion);
    put_u32(body, uint32_t(lobes.size() / 5));
    for (float v : lobes) put_u32(body, std::bit_cast<uint32_t>(v));
    out.write(kMagic.data(), kMagic.size());
    out.write(reinterpret_cast<const char*>(body.data()), std::streamsize(body.size()));
    std::vector<unsigned char> sum;
    put_u32(sum, fnv1a(body.data(), body.size()));
    out.write(reinterpret_cast<const char*>(sum.data()), 4);
    if (!out) throw VmmFormatError("failed to write VMM record");
}

std::vector<float> read_vmm_record(std::istream& in, int capacity) {
    std::array<unsigned char, 8> magic{};
    read_exact(in, magic.data(), magic.size(), "magic");
    if (std::memcmp(magic.data(), kMagic.data(), kMagic.size()) != 0)
        throw VmmFormatError("not a volguide VMM record");
    std::vector<unsigned char> body(8);
    read_exact(in, body.data(), 8, "header");
    uint32_t version = get_u32(body.data()), count = get_u32(body.data() + 4);
    if (version != kVmmFormatVersion)
        throw VmmFormatError("unsupported VMM format version " + std::to_string(version) + " (expected " +
                             std::to_string(kVmmFormatVersion) + ")");
    if (count > uint32_t(capacity))
        throw VmmFormatError("VMM record has " + std::to_string(count) + " lobes, capacity is " +
                             std::to_string(capacity));
    body.resize(8 + size_t(count) * 5 * 4);
    read_exact(in, body.data() + 8, body.size() - 8, "lobes");
    std::array<unsigned char, 4> sum{};
    read_exact(in, sum.data(), 4, "checksum");
    if (get_u32(sum.data()) != fnv1a(body.data(), body.size()))
        throw VmmFormatError("VMM record checksum mismatch");

    std::vector<float> lobes(size_t(count) * 5);
    for (size_t i = 0; i < lobes.size(); ++i)
        lobes[i] = std::bit_cast<float>(get_u32(body.data() + 8 + 4 * i));
    validate(lobes);
    return lobes;
}

}  // namespace volguide
