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
# Which Open PGL: VOLGUIDE_OPENPGL_SOURCE=0.7.1 (default, the release) or 0.8 (the unreleased devel
# snapshot 436c836, built with OPENPGL_EF_VSP_GUIDING=ON: the VSPG peer row, issue 37). Both export the
# same C symbols, so one build links exactly one of them; build the 0.8 peer in a build directory of
# its own (docs/openpgl.md).
#
# Sets VOLGUIDE_HAVE_OPENPGL (ON/OFF) and, when ON, the imported target openpgl::openpgl.

option(VOLGUIDE_WITH_OPENPGL "Use Intel Open PGL for the openpgl_volpath integrator when available" ON)
set(VOLGUIDE_OPENPGL_SOURCE "0.7.1" CACHE STRING
    "Open PGL version for openpgl_volpath: 0.7.1 (release) or 0.8 (devel 436c836, adds vsp=true)")
set_property(CACHE VOLGUIDE_OPENPGL_SOURCE PROPERTY STRINGS 0.7.1 0.8)
# Per version: tarball name, its sha256 (from ../shared/third_party/README.md: a changed tarball is an
# error, not a silent rebuild), the folder it unpacks to, the build tree's install folder and Open PGL's
# own configure options. 0.7.1 keeps the paths it always had, so existing build trees are reused.
if(VOLGUIDE_OPENPGL_SOURCE STREQUAL "0.7.1")
  set(tarball_name openpgl-0.7.1-src.tar.gz)
  set(VOLGUIDE_OPENPGL_SHA256 6a4e62d76b097f6bc1bf74b9c7fc1200de72510bb7555dfb036e27d71041e680)
  set(VOLGUIDE_OPENPGL_SRC_NAME openpgl-0.7.1)
  set(VOLGUIDE_OPENPGL_INSTALL_NAME openpgl-install)
  set(VOLGUIDE_OPENPGL_EXTRA_OPTIONS "")
elseif(VOLGUIDE_OPENPGL_SOURCE STREQUAL "0.8")
  set(tarball_name openpgl-0.8.0-devel-436c836-src.tar.gz)
  set(VOLGUIDE_OPENPGL_SHA256 af4fffed5f2b2d49826aa30164d095754884843227b55a2e7a397e2b098e5452)
  set(VOLGUIDE_OPENPGL_SRC_NAME openpgl-0.8.0-devel-436c836)
  set(VOLGUIDE_OPENPGL_INSTALL_NAME openpgl-0.8-install)
  set(VOLGUIDE_OPENPGL_EXTRA_OPTIONS "-DOPENPGL_EF_VSP_GUIDING=ON")
else()
  message(FATAL_ERROR "VOLGUIDE_OPENPGL_SOURCE='${VOLGUIDE_OPENPGL_SOURCE}': expected 0.7.1 or 0.8")
endif()
set(VOLGUIDE_OPENPGL_TARBALL "${CMAKE_SOURCE_DIR}/../shared/third_party/${tarball_name}"
    CACHE FILEPATH "Open PGL source tarball built into the build tree when no openpgl package is installed")
if(NOT VOLGUIDE_OPENPGL_TARBALL MATCHES "${tarball_name}$")
  message(FATAL_ERROR "VOLGUIDE_OPENPGL_TARBALL=${VOLGUIDE_OPENPGL_TARBALL} is not the "
                      "${VOLGUIDE_OPENPGL_SOURCE} tarball ${tarball_name}: unset it when changing VOLGUIDE_OPENPGL_SOURCE")
endif()
set(VOLGUIDE_HAVE_OPENPGL OFF)

# Builds the tarball into ${CMAKE_BINARY_DIR}/third_party/<install name> (once; later configures
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
  set(src_dir ${root}/${VOLGUIDE_OPENPGL_SRC_NAME})
  set(build_dir ${root}/${VOLGUIDE_OPENPGL_SRC_NAME}-build)
  if(VOLGUIDE_OPENPGL_SOURCE STREQUAL "0.7.1")
    set(build_dir ${root}/openpgl-build)
  endif()
  if(NOT EXISTS ${src_dir}/CMakeLists.txt)
    message(FATAL_ERROR "${tarball}: did not unpack to ${src_dir}")
  endif()
  cmake_host_system_information(RESULT cores QUERY NUMBER_OF_LOGICAL_CORES)
  foreach(step
      "${CMAKE_COMMAND};-S;${src_dir};-B;${build_dir};-DCMAKE_BUILD_TYPE=Release;-DCMAKE_INSTALL_PREFIX=${install_dir};-DOPENPGL_BUILD_TOOLS=OFF;-DCMAKE_POSITION_INDEPENDENT_CODE=ON;${VOLGUIDE_OPENPGL_EXTRA_OPTIONS}"
      "${CMAKE_COMMAND};--build;${build_dir};-j;${cores}"
      "${CMAKE_COMMAND};--install;${build_dir}")
    execute_process(COMMAND ${step} RESULT_VARIABLE rc OUTPUT_FILE ${root}/openpgl-build.log
                    ERROR_FILE ${root}/openpgl-build.log)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "Open PGL: '${step}' failed (${rc}); see ${root}/openpgl-build.log")
    endif()
  endforeach()
  file(TOUCH ${install_dir}/.volguide-built)
endfunction()

if(VOLGUIDE_WITH_OPENPGL)
  find_package(openpgl ${VOLGUIDE_OPENPGL_SOURCE} CONFIG QUIET)
  if(NOT openpgl_FOUND AND EXISTS ${VOLGUIDE_OPENPGL_TARBALL})
    set(install_dir ${CMAKE_BINARY_DIR}/third_party/${VOLGUIDE_OPENPGL_INSTALL_NAME})
    volguide_build_openpgl_from_tarball(${VOLGUIDE_OPENPGL_TARBALL} ${install_dir})
    file(GLOB config_dir LIST_DIRECTORIES true ${install_dir}/lib*/cmake/openpgl-*)
    unset(openpgl_DIR CACHE)
    find_package(openpgl ${VOLGUIDE_OPENPGL_SOURCE} CONFIG REQUIRED PATHS ${config_dir} NO_DEFAULT_PATH)
  endif()
  # Open PGL's version file accepts any newer 0.x for an older request: check the one we asked for.
  if(openpgl_FOUND AND NOT openpgl_VERSION MATCHES "^${VOLGUIDE_OPENPGL_SOURCE}")
    message(FATAL_ERROR "Open PGL: VOLGUIDE_OPENPGL_SOURCE=${VOLGUIDE_OPENPGL_SOURCE} but openpgl_DIR=${openpgl_DIR} "
                        "is version ${openpgl_VERSION}: point openpgl_DIR at a ${VOLGUIDE_OPENPGL_SOURCE} install or unset it")
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
