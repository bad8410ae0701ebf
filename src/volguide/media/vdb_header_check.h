#pragma once
// Bounds a .vdb file's header and grid metadata by the file's size before OpenVDB reads them.
// OpenVDB (MetaMap::readMeta, readString) allocates every string and metadata value at the length
// the file declares before reading it: a fuzzed 98 KB file made it allocate and clear gigabytes
// (docs/reliability.md). Only the layout of format 222 and later is walked (what OpenVDB 3 to 10
// write); older files are refused, as are streams without grid offsets.
#include <string>

namespace volguide {

// Throws InputError ("cannot read the .vdb file: ...") naming the file when a length or offset in the header, the file's metadata, a
// grid descriptor or a grid's metadata does not fit in the file.
void check_vdb_header(const std::string& path);

}  // namespace volguide
