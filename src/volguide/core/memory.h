#pragma once
// How much memory this machine has: the bound for allocations whose size comes from input (film
// sizes, dense grids), checked before allocating so that an absurd file is an error naming it
// rather than an out-of-memory kill.
#include <cstdint>
#include <string>

namespace volguide {

// Physical memory in bytes (sysconf); 0 when the system does not say.
uint64_t physical_memory_bytes();

// What one allocation sized by input may take: the physical memory, or less when the environment
// sets VOLGUIDE_MEMORY_LIMIT_MB (a farm job's share of a node; the fuzzers use 1024 to match their
// memory limit). 0 = unknown, nothing bounded by it. A malformed variable is an error, not ignored.
uint64_t memory_budget_bytes();
// "this machine's 23.5 GiB" or "the VOLGUIDE_MEMORY_LIMIT_MB budget of 1.0 GiB", for messages.
std::string memory_budget_description();

// "1.5 GiB", "12.0 MiB", "512 B": for messages and `volguide info`.
std::string format_bytes(uint64_t bytes);

}  // namespace volguide
