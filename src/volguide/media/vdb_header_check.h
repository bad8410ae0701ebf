#pragma once
// Bounds a .vdb file's header and grid metadata by the file's size before OpenVDB reads them.
// OpenVDB (MetaMap::readMeta, readString) allocates every string and metadata value at the length
// the file declares before reading it: a fuzzed 98 KB file made it allocate and clear gigabytes
// (docs/reliability.md). Values of OpenVDB's fixed-size metadata types are read by their layout,
// whatever size the file declares, so the declared size must match it or the reader falls out of step
// (a "vec4i" declared 12 bytes long led to a 1.7 GB string). Only the layout of format 222 and later
// is walked (what OpenVDB 3 to 10 write); older files are refused, as are streams without grid
// offsets. Each grid's tree is walked too: OpenVDB allocates every node (a 32^3 internal node's full
// child mask: 32768 nodes, 1.1 GB) before reading it and reads on when the stream ran dry, so every
// node, compressed chunk and voxel buffer must lie in the file, and the nodes' memory within the
// budget (core/memory.h). Point grids' trees are bounded at their root only (their type is refused
// before reading).
#include <cstdint>
#include <optional>
#include <string>

namespace volguide {

// Throws InputError ("cannot read the .vdb file: ...") naming the file when a length or offset in the header, the file's metadata, a
// grid descriptor, a grid's metadata or a grid's transform type does not fit in the file, when a
// fixed-size metadata value declares another size than its type's layout, or when delayed-load
// metadata declares arrays that do not fit in its value or more leaves than the file can hold, when a
// tree's nodes or buffers run past the file, its root children are out of OpenVDB's order, a Blosc
// chunk's header disagrees with the chunk, or its nodes need more memory than the budget.
void check_vdb_header(const std::string& path);

// The bytes OpenVDB reads for a value of a fixed-size metadata type it registers ("vec3i": 12), or
// nothing for other types ("string", "__delayedload", unregistered ones are read by declared size).
std::optional<uint32_t> vdb_metadata_layout_bytes(const std::string& type);

}  // namespace volguide
