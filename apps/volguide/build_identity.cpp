#include "build_identity.h"

#include "volguide_build_identity.h"  // generated at build time (cmake/build_identity.cmake)

namespace volguide::cli {

const char* build_identity() { return VOLGUIDE_BUILD_IDENTITY; }

}  // namespace volguide::cli
