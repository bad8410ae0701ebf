// The libFuzzer entry of one target: VOLGUIDE_FUZZ_ENTRY names the fuzz_<reader> function
// (tests/fuzz/CMakeLists.txt builds one executable per target with -fsanitize=fuzzer).
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return volguide::fuzz::VOLGUIDE_FUZZ_ENTRY(data, size);
}
