#pragma once
// The readers take paths, so a fuzz input is written to a file first: one private directory per
// process (under the system temp dir), one file per extension, overwritten by every input.
#include <cstddef>
#include <cstdint>
#include <string>

namespace volguide::fuzz {

// Writes the bytes to <private dir>/input<extension> and returns that path.
std::string write_fuzz_input(const uint8_t* data, size_t size, const std::string& extension);

}  // namespace volguide::fuzz
