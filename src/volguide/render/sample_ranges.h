#pragma once
// Sets of sample indices as sorted, disjoint, coalesced ranges [first, first + count): what a part
// of a distributed render holds ("0:16,32:8" in its EXR header).
#include <cstdint>
#include <string>
#include <vector>

namespace volguide {

struct SampleRange {
    uint64_t first = 0, count = 0;
    uint64_t end() const { return first + count; }
    bool operator==(const SampleRange&) const = default;
};
using SampleRanges = std::vector<SampleRange>;

// "FIRST:COUNT[,FIRST:COUNT...]"; "" for none. Throws std::invalid_argument for anything else.
std::string format_ranges(const SampleRanges& ranges);
SampleRanges parse_ranges(const std::string& text);
// Sorted and coalesced (touching ranges joined, empty ones dropped); overlaps are the caller's to check.
SampleRanges normalized(SampleRanges ranges);
// The first overlap of two sorted range sets, if any (count 0 when none).
SampleRange first_overlap(const SampleRanges& a, const SampleRanges& b);
// The holes between the first and the last index of a normalized set.
SampleRanges gaps(const SampleRanges& ranges);
uint64_t total_count(const SampleRanges& ranges);

}  // namespace volguide
