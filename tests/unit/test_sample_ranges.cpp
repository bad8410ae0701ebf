// Sample range sets of distributed-render parts (render/sample_ranges.h).
#include <gtest/gtest.h>

#include <stdexcept>

#include "volguide/render/sample_ranges.h"

namespace volguide {
namespace {

TEST(SampleRanges, FormatAndParseRoundTrip) {
    const SampleRanges r{{0, 16}, {32, 8}};
    EXPECT_EQ(format_ranges(r), "0:16,32:8");
    EXPECT_EQ(parse_ranges("0:16,32:8"), r);
    EXPECT_TRUE(parse_ranges("").empty());
    for (const char* bad : {"3", "a:b", "1:2,", ":4", "1:-2", "1:2:3", "18446744073709551615:2"})
        EXPECT_THROW(parse_ranges(bad), std::invalid_argument) << bad;
}

TEST(SampleRanges, NormalizedSortsJoinsAndDropsEmptyRanges) {
    EXPECT_EQ(normalized({{8, 4}, {0, 4}, {4, 4}, {20, 0}, {14, 2}}), (SampleRanges{{0, 12}, {14, 2}}));
    EXPECT_EQ(total_count({{0, 12}, {14, 2}}), 14u);
}

TEST(SampleRanges, OverlapsAndGaps) {
    EXPECT_EQ(first_overlap({{0, 4}}, {{3, 4}}), (SampleRange{3, 1}));
    EXPECT_EQ(first_overlap({{0, 4}}, {{4, 4}}).count, 0u);
    EXPECT_EQ(gaps({{0, 4}, {6, 2}, {10, 1}}), (SampleRanges{{4, 2}, {8, 2}}));
    EXPECT_TRUE(gaps({{0, 4}}).empty());
}

}  // namespace
}  // namespace volguide
