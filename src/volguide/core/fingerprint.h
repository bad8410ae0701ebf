#pragma once
// 64-bit FNV-1a fingerprints of byte strings, printed as 16 hex digits: what distributed renders
// (train / render --field / --samples / merge) compare to tell whether two files belong together.
// Not cryptographic: it catches mix-ups and corruption, not forgeries.
#include <cstdint>
#include <string>
#include <string_view>

#include <fmt/format.h>

namespace volguide {

inline uint64_t fnv1a64(std::string_view bytes, uint64_t h = 14695981039346656037ull) {
    for (char c : bytes) h = (h ^ uint64_t(uint8_t(c))) * 1099511628211ull;
    return h;
}

inline std::string fingerprint_hex(uint64_t h) { return fmt::format("{:016x}", h); }

inline std::string fingerprint(std::string_view bytes) { return fingerprint_hex(fnv1a64(bytes)); }

}  // namespace volguide
