#pragma once
// The identity of this build (its source, compiler and build type; cmake/build_identity.cmake), what a
// render checkpoint records so that another build's checkpoint is refused.
namespace volguide::cli {

const char* build_identity();

}  // namespace volguide::cli
