#pragma once
// Bounds an EXR header by the file's size before OpenEXR reads it. OpenEXR allocates each header
// attribute at the size the file declares (up to 2 GiB) before noticing that the file is shorter:
// a fuzzer's 500-byte file made one read allocate and clear gigabytes (docs/reliability.md).
#include <string>

namespace volguide {

// Walks the header's attributes (of every part, for multi-part files) and throws InputError naming
// the file when one is malformed or declares more bytes than the file has left, or when a part's
// data window or tiles would make OpenEXR allocate decode buffers (whole blocks of scanlines, whole
// tiles) larger than the file could fill at EXR's best compression, or than the memory budget.
void check_exr_header(const std::string& path);

// The size of an EXR's data window [min, max] (inclusive, as OpenEXR gives it), checked: positive,
// within int, and the float buffers of `channels` channels no larger than the file could hold at
// the best compression ratio EXR has, nor than the machine's memory. InputError otherwise.
struct ExrSize {
    int width = 0, height = 0;
};
ExrSize checked_exr_size(const std::string& path, int min_x, int min_y, int max_x, int max_y, size_t channels);

}  // namespace volguide
