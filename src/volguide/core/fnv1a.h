#pragma once
// 64-bit FNV-1a over a byte string: the checksum of saved guiding fields (guiding/field_io) and the
// fingerprints of distributed renders (core/fingerprint.h). Header-only, no dependencies, so the
// installed guiding library can use it. Not cryptographic: it catches corruption and mix-ups.
#include <cstdint>
#include <string_view>

namespace volguide {

inline uint64_t fnv1a64(std::string_view bytes, uint64_t h = 14695981039346656037ull) {
    for (char c : bytes) h = (h ^ uint64_t(uint8_t(c))) * 1099511628211ull;
    return h;
}

}  // namespace volguide
