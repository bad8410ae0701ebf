# Intel Open PGL (the peer guiding library of the `openpgl_volpath` integrator, issue 19).
#
# Used whenever it is available, in this order:
#   1. an installed `openpgl` CMake package (find_package, e.g. -Dopenpgl_DIR=...);
#   2. the source tarball kept beside the repository at ../shared/third_party/ (Open PGL is not in
#      Debian and machines here cannot download it), built once into the build tree at configure
#      time with Debian's TBB only (no superbuild: it downloads TBB, ISPC and OIDN; no network).
# Without either, volguide builds without it: VOLGUIDE_HAVE_OPENPGL is 0 and a scene naming
# `openpgl_volpath` fails with an error saying so. -DVOLGUIDE_WITH_OPENPGL=OFF forces that.
#
# Sets VOLGUIDE_HAVE_OPENPGL (ON/OFF) and, when ON, the imported target openpgl::openpgl.

option(VOLGUIDE_WITH_OPENPGL "Use Intel Open PGL for the openpgl_volpath integrator when available" ON)
set(VOLGUIDE_OPENPGL_TARBALL "${CMAKE_SOURCE_DIR}/../shared/third_party/openpgl-0.7.1-src.tar.gz"
    CACHE FILEPATH "Open PGL source tarball built into the build tree when no openpgl package is installed")
# sha256 from ../shared/third_party/README.md: a changed tarball is an error, not a silent rebuild.
set(VOLGUIDE_OPENPGL_SHA256 6a4e62d76b097f6bc1bf74b9c7fc1200de72510bb7555dfb036e27d71041e680)
set(VOLGUIDE_HAVE_OPENPGL OFF)

# Builds the tarball into ${CMAKE_BINARY_DIR}/third_party/openpgl-install (once; later configures
# reuse the install). Fails the configure on a build error: a present tarball that does not build
# is a broken checkout, not a reason to drop the integrator silently.
function(volguide_build_openpgl_from_tarball tarball install_dir)
  set(root ${CMAKE_BINARY_DIR}/third_party)
  if(EXISTS ${install_dir}/.volguide-built)
    return()
  endif()
  file(SHA256 ${tarball} sha)
  if(NOT sha STREQUAL VOLGUIDE_OPENPGL_SHA256)
    message(FATAL_ERROR "${tarball}: sha256 ${sha}, expected ${VOLGUIDE_OPENPGL_SHA256}")
  endif()
  message(STATUS "Open PGL: building ${tarball} into ${install_dir} (about 75 s per core, once)")
  file(MAKE_DIRECTORY ${root})
  file(ARCHIVE_EXTRACT INPUT ${tarball} DESTINATION ${root})
  file(GLOB src_dir LIST_DIRECTORIES true ${root}/openpgl-*/CMakeLists.txt)
  list(GET src_dir 0 src_dir)
  get_filename_component(src_dir ${src_dir} DIRECTORY)
  cmake_host_system_information(RESULT cores QUERY NUMBER_OF_LOGICAL_CORES)
  foreach(step
      "${CMAKE_COMMAND};-S;${src_dir};-B;${root}/openpgl-build;-DCMAKE_BUILD_TYPE=Release;-DCMAKE_INSTALL_PREFIX=${install_dir};-DOPENPGL_BUILD_TOOLS=OFF;-DCMAKE_POSITION_INDEPENDENT_CODE=ON"
      "${CMAKE_COMMAND};--build;${root}/openpgl-build;-j;${cores}"
      "${CMAKE_COMMAND};--install;${root}/openpgl-build")
    execute_process(COMMAND ${step} RESULT_VARIABLE rc OUTPUT_FILE ${root}/openpgl-build.log
                    ERROR_FILE ${root}/openpgl-build.log)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "Open PGL: '${step}' failed (${rc}); see ${root}/openpgl-build.log")
    endif()
  endforeach()
  file(TOUCH ${install_dir}/.volguide-built)
endfunction()

if(VOLGUIDE_WITH_OPENPGL)
  find_package(openpgl 0.7 CONFIG QUIET)
  if(NOT openpgl_FOUND AND EXISTS ${VOLGUIDE_OPENPGL_TARBALL})
    set(install_dir ${CMAKE_BINARY_DIR}/third_party/openpgl-install)
    volguide_build_openpgl_from_tarball(${VOLGUIDE_OPENPGL_TARBALL} ${install_dir})
    file(GLOB config_dir LIST_DIRECTORIES true ${install_dir}/lib*/cmake/openpgl-*)
    find_package(openpgl 0.7 CONFIG REQUIRED PATHS ${config_dir} NO_DEFAULT_PATH)
  endif()
  if(openpgl_FOUND)
    set(VOLGUIDE_HAVE_OPENPGL ON)
    message(STATUS "Open PGL ${openpgl_VERSION}: openpgl_volpath is built in (${openpgl_DIR})")
  else()
    message(STATUS "Open PGL: no openpgl package and no ${VOLGUIDE_OPENPGL_TARBALL}: "
                   "built without openpgl_volpath")
  endif()
else()
  message(STATUS "Open PGL: disabled (VOLGUIDE_WITH_OPENPGL=OFF)")
endif()
