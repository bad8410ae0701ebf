#include "volguide/render/sample_ranges.h"

#include <algorithm>
#include <charconv>
#include <stdexcept>

namespace volguide {

namespace {

uint64_t parse_uint(const std::string& text, const std::string& whole) {
    uint64_t v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || text.empty())
        throw std::invalid_argument("bad sample range '" + whole + "' (expected FIRST:COUNT[,FIRST:COUNT...])");
    return v;
}

}  // namespace

std::string format_ranges(const SampleRanges& ranges) {
    std::string s;
    for (size_t i = 0; i < ranges.size(); ++i)
        s += (i ? "," : "") + std::to_string(ranges[i].first) + ":" + std::to_string(ranges[i].count);
    return s;
}

SampleRanges parse_ranges(const std::string& text) {
    SampleRanges ranges;
    if (text.empty()) return ranges;
    size_t start = 0;
    while (start <= text.size()) {
        size_t comma = text.find(',', start);
        if (comma == std::string::npos) comma = text.size();
        const std::string item = text.substr(start, comma - start);
        const size_t colon = item.find(':');
        if (colon == std::string::npos)
            throw std::invalid_argument("bad sample range '" + text + "' (expected FIRST:COUNT[,FIRST:COUNT...])");
        SampleRange r{parse_uint(item.substr(0, colon), text), parse_uint(item.substr(colon + 1), text)};
        if (r.end() < r.first) throw std::invalid_argument("sample range '" + item + "' overflows");
        ranges.push_back(r);
        start = comma + 1;
    }
    return ranges;
}

SampleRanges normalized(SampleRanges ranges) {
    std::sort(ranges.begin(), ranges.end(), [](const SampleRange& a, const SampleRange& b) { return a.first < b.first; });
    SampleRanges out;
    for (const SampleRange& r : ranges) {
        if (r.count == 0) continue;
        if (!out.empty() && r.first <= out.back().end())
            out.back().count = std::max(out.back().end(), r.end()) - out.back().first;
        else
            out.push_back(r);
    }
    return out;
}

SampleRange first_overlap(const SampleRanges& a, const SampleRanges& b) {
    for (const SampleRange& x : a)
        for (const SampleRange& y : b) {
            const uint64_t lo = std::max(x.first, y.first), hi = std::min(x.end(), y.end());
            if (lo < hi) return {lo, hi - lo};
        }
    return {};
}

SampleRanges gaps(const SampleRanges& ranges) {
    SampleRanges out;
    for (size_t i = 1; i < ranges.size(); ++i)
        if (ranges[i].first > ranges[i - 1].end())
            out.push_back({ranges[i - 1].end(), ranges[i].first - ranges[i - 1].end()});
    return out;
}

uint64_t total_count(const SampleRanges& ranges) {
    uint64_t n = 0;
    for (const SampleRange& r : ranges) n += r.count;
    return n;
}

}  // namespace volguide
