#pragma once
// Binary, versioned file format of a trained guiding field (`save_field` / `load_field`).
//
// Layout (little-endian):
//   8 bytes   magic "VGFIELD\0"
//   u32       format version (kFieldFormatVersion)
//   6 x f32   bounds (lo, hi)
//   u32       node count, then per node: f32 split, u32 child, u8 axis
//   u32       leaf count, then per leaf: 3 x f32 fluence, u32 samples, f32 medium fraction
//             (< 0: not measured; absent in version 2, whose fields load as not measured), u8 valid, for a valid
//             leaf its VMM as a vmm_io record, u8 valid_indirect, and if set the indirect VMM
//   u64       FNV-1a checksum of everything between the magic and the checksum
// Loading checks the magic, version, checksum, sizes, the tree's structure (SpatialTree::from_nodes),
// finite non-negative fluence and every VMM record; any problem throws FieldFormatError naming it.
// Saving writes through a temporary file and renames, so an interrupted save leaves no partial file.
#include <stdexcept>
#include <string>

#include "volguide/guiding/guiding_field.h"

namespace volguide {

// 2: per-leaf indirect VMM; 3: per-leaf medium fraction. Version 2 files are still read.
inline constexpr uint32_t kFieldFormatVersion = 3;

class FieldFormatError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

std::string serialize_field(const GuidingField& field);
GuidingField deserialize_field(const std::string& bytes);

// File variants; errors name the file.
void save_field(const std::string& path, const GuidingField& field);
GuidingField load_field(const std::string& path);

}  // namespace volguide
