#include "volguide/core/memory.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <stdexcept>

namespace volguide {

uint64_t physical_memory_bytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page_size <= 0) return 0;
    return uint64_t(pages) * uint64_t(page_size);
}

namespace {

// The limit from VOLGUIDE_MEMORY_LIMIT_MB in bytes, 0 when unset.
uint64_t environment_limit_bytes() {
    const char* text = std::getenv("VOLGUIDE_MEMORY_LIMIT_MB");
    if (!text || !*text) return 0;
    char* end = nullptr;
    errno = 0;
    const unsigned long long mb = std::strtoull(text, &end, 10);
    if (errno != 0 || *end != '\0' || mb == 0 || mb > (uint64_t(1) << 40))
        throw std::invalid_argument(fmt::format("VOLGUIDE_MEMORY_LIMIT_MB=\"{}\" is not a number of megabytes", text));
    return uint64_t(mb) << 20;
}

}  // namespace

uint64_t memory_budget_bytes() {
    const uint64_t physical = physical_memory_bytes(), limit = environment_limit_bytes();
    if (limit == 0) return physical;
    return physical == 0 ? limit : std::min(physical, limit);
}

std::string memory_budget_description() {
    const uint64_t physical = physical_memory_bytes(), limit = environment_limit_bytes();
    if (limit != 0 && (physical == 0 || limit < physical))
        return "the VOLGUIDE_MEMORY_LIMIT_MB budget of " + format_bytes(limit);
    return "this machine's " + format_bytes(physical);
}

std::string format_bytes(uint64_t bytes) {
    static const char* units[] = {"KiB", "MiB", "GiB", "TiB", "PiB"};
    if (bytes < 1024) return fmt::format("{} B", bytes);
    double v = double(bytes) / 1024.0;
    int u = 0;
    while (v >= 1024.0 && u < 4) v /= 1024.0, ++u;
    return fmt::format("{:.1f} {}", v, units[u]);
}

}  // namespace volguide
