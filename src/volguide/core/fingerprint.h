#pragma once
// 64-bit FNV-1a fingerprints of byte strings, printed as 16 hex digits: what distributed renders
// (train / render --field / --samples / merge) compare to tell whether two files belong together.
// Not cryptographic: it catches mix-ups and corruption, not forgeries.
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "volguide/core/fnv1a.h"

namespace volguide {

inline std::string fingerprint_hex(uint64_t h) { return fmt::format("{:016x}", h); }

inline std::string fingerprint(std::string_view bytes) { return fingerprint_hex(fnv1a64(bytes)); }

}  // namespace volguide
