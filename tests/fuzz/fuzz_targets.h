#pragma once
// Fuzz entry points of volguide's readers (docs/reliability.md). Each takes one input as bytes,
// feeds it to one reader the way a user's file would reach it, and returns 0. The readers' contract
// is that bad input throws InputError (FieldFormatError for saved fields) naming the file; the entry
// points catch exactly those. Anything else — another exception, a crash, a sanitizer report, a
// hang — escapes and is a finding. The same functions serve the libFuzzer mains
// (libfuzzer_main.cpp) and the regression test that replays tests/fuzz/{corpus,regression}
// (test_fuzz_regression.cpp) in the normal build.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace volguide::fuzz {

int fuzz_scene(const uint8_t* data, size_t size);     // Mitsuba XML → Scene, no rendering
int fuzz_vol(const uint8_t* data, size_t size);       // Mitsuba .vol grid
int fuzz_vdb(const uint8_t* data, size_t size);       // OpenVDB file, grid "density"
int fuzz_field(const uint8_t* data, size_t size);     // saved guiding field (field_io)
int fuzz_obj(const uint8_t* data, size_t size);       // Wavefront OBJ mesh
int fuzz_ply(const uint8_t* data, size_t size);       // Stanford PLY mesh
int fuzz_exr_part(const uint8_t* data, size_t size);  // EXR part of a render (channels + volguide.* metadata)
int fuzz_serialized(const uint8_t* data, size_t size);  // Mitsuba .serialized mesh (zlib), shape 0 and 1
int fuzz_image(const uint8_t* data,
               size_t size);  // texture / envmap image (EXR, PNG, JPEG, BMP, TGA)

int fuzz_checkpoint(const uint8_t* data, size_t size);  // render checkpoint (render --resume)

using FuzzEntry = int (*)(const uint8_t*, size_t);
struct FuzzTarget {
    const char* name;  // also the folder name under tests/fuzz/corpus and tests/fuzz/regression
    FuzzEntry entry;
};
// Every target, in one table so the regression test and `make fuzz` cannot miss one.
const std::vector<FuzzTarget>& fuzz_targets();

}  // namespace volguide::fuzz
