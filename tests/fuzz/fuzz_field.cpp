// Saved guiding fields (guiding/field_io): magic, version, checksum, tree structure, VMM records.
// The bytes go to deserialize_field directly (load_field only adds reading the file).
#include "fuzz_targets.h"
#include "volguide/guiding/field_io.h"

namespace volguide::fuzz {

int fuzz_field(const uint8_t* data, size_t size) {
    try {
        (void)deserialize_field(std::string(reinterpret_cast<const char*>(data), size));
    } catch (const FieldFormatError&) {
        // field_io's contract for a bad field: an error naming the problem.
    }
    return 0;
}

}  // namespace volguide::fuzz
