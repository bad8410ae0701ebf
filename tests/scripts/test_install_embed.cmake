# CTest `install_embed` (cmake -P): installs the guiding core of the current build into a temporary
# prefix, checks that every installed header's volguide includes are installed too, then configures,
# builds and runs examples/embed against that prefix alone (find_package(volguide)).
# Variables: BUILD_DIR, SOURCE_DIR, WORK_DIR (emptied first), CXX_COMPILER, CXX_LAUNCHER (optional).
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR CXX_COMPILER)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "test_install_embed.cmake: -D${var}=... is required")
  endif()
endforeach()

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}): ${ARGN}")
  endif()
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})
run("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

# The installed headers are closed under their volguide includes.
file(GLOB_RECURSE headers ${prefix}/include/volguide/*.h)
list(LENGTH headers header_count)
if(header_count EQUAL 0)
  message(FATAL_ERROR "no headers installed under ${prefix}/include/volguide")
endif()
foreach(header ${headers})
  file(STRINGS ${header} includes REGEX "^#include \"volguide/")
  foreach(line ${includes})
    string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" included "${line}")
    if(NOT EXISTS ${prefix}/include/${included})
      message(FATAL_ERROR "${header} includes ${included}, which is not installed")
    endif()
  endforeach()
endforeach()
message(STATUS "${header_count} installed headers, their volguide includes all installed")

set(launcher)
if(CXX_LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${CXX_LAUNCHER})
endif()
run("configure examples/embed" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/embed -B ${WORK_DIR}/build
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX_COMPILER} ${launcher})
run("build examples/embed" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run("slab_embed" ${WORK_DIR}/build/slab_embed ${WORK_DIR})
file(REMOVE_RECURSE ${WORK_DIR})
