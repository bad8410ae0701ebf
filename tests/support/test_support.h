#pragma once
// Shared helpers for volguide's tests.
#include <string>

namespace volguide::test {

// Root of the repository and of ../shared (read-only test data; may be absent outside CI).
inline std::string source_dir() { return VOLGUIDE_SOURCE_DIR; }
inline std::string shared_dir() { return VOLGUIDE_SHARED_DIR; }
inline std::string cli_path() { return VOLGUIDE_CLI; }

}  // namespace volguide::test
