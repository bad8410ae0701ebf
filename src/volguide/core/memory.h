#pragma once
// How much memory this machine has: the bound for allocations whose size comes from input (film
// sizes, dense grids), checked before allocating so that an absurd file is an error naming it
// rather than an out-of-memory kill.
#include <cstdint>
#include <string>

namespace volguide {

// Physical memory in bytes (sysconf); 0 when the system does not say (then nothing is bounded by it).
uint64_t physical_memory_bytes();

// "1.5 GiB", "12.0 MiB", "512 B": for messages and `volguide info`.
std::string format_bytes(uint64_t bytes);

}  // namespace volguide
