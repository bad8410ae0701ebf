# The guiding core as a library other renderers build against (docs/guiding-api.md): the vMF
# mixtures (vmm/) and the guiding field with its decisions (guiding/). It needs only TBB and the
# header-only parts of core/ and media/ listed below, none of volguide's scene, so it is its own
# target; the full `volguide` library links it. Installed, it is `volguide::volguide`:
#   find_package(volguide)  +  target_link_libraries(app PRIVATE volguide::volguide)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# Version of the installed API (the package's version file). The field file format has its own
# version, kFieldFormatVersion (guiding/field_io.h), checked on load.
set(VOLGUIDE_API_VERSION 0.2.0)

# Folders whose sources make up the library (the full library's glob leaves them out).
set(VOLGUIDE_GUIDING_MODULES "guiding|vmm")
file(GLOB VOLGUIDE_GUIDING_SOURCES CONFIGURE_DEPENDS
  ${CMAKE_SOURCE_DIR}/src/volguide/guiding/*.cpp ${CMAKE_SOURCE_DIR}/src/volguide/vmm/*.cpp)
add_library(volguide_guiding STATIC ${VOLGUIDE_GUIDING_SOURCES})
volguide_unity_build(volguide_guiding)
target_include_directories(volguide_guiding PUBLIC
  $<BUILD_INTERFACE:${CMAKE_SOURCE_DIR}/src> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
# TBB is public: roulette_splitting.h keeps its statistics in a tbb::enumerable_thread_specific.
# Google Highway (libhwy-dev) compiles the vectorised vMF kernels (vmm/vmf_simd.cpp) for every x86
# target and dispatches at run time; no installed header includes it, but the static library needs
# its runtime (target detection), so it is a dependency of the package.
find_package(hwy REQUIRED)
target_link_libraries(volguide_guiding PUBLIC TBB::tbb hwy::hwy)
# Highway's foreach_target.h includes the file once per target: it must be compiled alone.
set_source_files_properties(${CMAKE_SOURCE_DIR}/src/volguide/vmm/vmf_simd.cpp PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
target_compile_features(volguide_guiding PUBLIC cxx_std_20)
# Position-independent, so that a renderer can link it into a shared plugin.
set_target_properties(volguide_guiding PROPERTIES EXPORT_NAME volguide POSITION_INDEPENDENT_CODE ON)
# (see the full library's -fno-semantic-interposition in CMakeLists.txt)
target_compile_options(volguide_guiding PRIVATE $<$<CXX_COMPILER_ID:GNU,Clang>:-fno-semantic-interposition>)

# Installed headers: the two modules' headers and the header-only files of core/ and media/ they
# include (no .cpp of core/ or media/ is needed). The install test (tests/scripts/
# test_install_embed.cmake) fails when an installed header includes one that is not installed.
file(GLOB VOLGUIDE_GUIDING_HEADERS RELATIVE ${CMAKE_SOURCE_DIR}/src CONFIGURE_DEPENDS
  ${CMAKE_SOURCE_DIR}/src/volguide/guiding/*.h ${CMAKE_SOURCE_DIR}/src/volguide/vmm/*.h)
list(APPEND VOLGUIDE_GUIDING_HEADERS
  volguide/core/bbox.h volguide/core/color.h volguide/core/frame.h volguide/core/math.h
  volguide/core/object.h volguide/core/ray.h volguide/core/vec.h
  volguide/media/guided_tracking.h volguide/media/phase.h)
foreach(header ${VOLGUIDE_GUIDING_HEADERS})
  get_filename_component(dir ${header} DIRECTORY)
  install(FILES ${CMAKE_SOURCE_DIR}/src/${header} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/${dir})
endforeach()

set(VOLGUIDE_PACKAGE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/volguide)
install(TARGETS volguide_guiding EXPORT volguideTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT volguideTargets NAMESPACE volguide:: DESTINATION ${VOLGUIDE_PACKAGE_DIR})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/volguideConfig.cmake.in
  ${CMAKE_BINARY_DIR}/volguideConfig.cmake INSTALL_DESTINATION ${VOLGUIDE_PACKAGE_DIR})
# 0.x: a new minor version may change the API.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/volguideConfigVersion.cmake
  VERSION ${VOLGUIDE_API_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/volguideConfig.cmake ${CMAKE_BINARY_DIR}/volguideConfigVersion.cmake
  DESTINATION ${VOLGUIDE_PACKAGE_DIR})
