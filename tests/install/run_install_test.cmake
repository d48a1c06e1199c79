# Run by ctest (test install_and_consume) as `cmake -D... -P run_install_test.cmake`:
#  1. cmake --install the granule build tree GRANULE_BUILD_DIR into the empty prefix PREFIX;
#  2. configure CONSUMER_SOURCE_DIR (a downstream project that calls find_package(granule))
#     in CONSUMER_BUILD_DIR with CMAKE_PREFIX_PATH=PREFIX, as the README's recipe does (Release),
#     build it and run its programs (with GRANULE_MPI=ON also one that links granule::mpi);
#  3. if GRANULE_SOURCE_DIR is set: configure CONSUMER_SOURCE_DIR/subdirectory (a project that
#     add_subdirectory()s granule) in CONSUMER_BUILD_DIR-subdirectory, build and install it into
#     PREFIX-subdirectory, and check that its program is there and granule's headers are not.
# Any failing step stops the script with a non-zero exit code.
foreach(var GRANULE_BUILD_DIR PREFIX CONSUMER_SOURCE_DIR CONSUMER_BUILD_DIR CXX_COMPILER GENERATOR)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "run_install_test.cmake: ${var} is not set")
  endif()
endforeach()

function(run_step what)
  message(STATUS "install test: ${what}")
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install test: '${what}' failed (${rc})")
  endif()
endfunction()

set(sub_build "${CONSUMER_BUILD_DIR}-subdirectory")
set(sub_prefix "${PREFIX}-subdirectory")
file(REMOVE_RECURSE "${PREFIX}" "${CONSUMER_BUILD_DIR}" "${sub_build}" "${sub_prefix}")

set(config_args)
if(DEFINED GRANULE_CONFIG AND NOT GRANULE_CONFIG STREQUAL "")
  set(config_args --config "${GRANULE_CONFIG}")
endif()
run_step("install into ${PREFIX}"
  "${CMAKE_COMMAND}" --install "${GRANULE_BUILD_DIR}" --prefix "${PREFIX}" ${config_args})

foreach(f include/granule/core/dimension.hpp lib/cmake/granule/granuleConfig.cmake
          lib/cmake/granule/granuleConfigVersion.cmake lib/cmake/granule/granuleTargets.cmake)
  if(NOT EXISTS "${PREFIX}/${f}")
    message(FATAL_ERROR "install test: ${PREFIX}/${f} was not installed")
  endif()
endforeach()

run_step("configure the downstream project"
  "${CMAKE_COMMAND}" -S "${CONSUMER_SOURCE_DIR}" -B "${CONSUMER_BUILD_DIR}" -G "${GENERATOR}"
  "-DCMAKE_PREFIX_PATH=${PREFIX}" "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
  -DCMAKE_BUILD_TYPE=Release "-DGRANULE_EXPECT_MPI=${GRANULE_MPI}")
run_step("build the downstream project"
  "${CMAKE_COMMAND}" --build "${CONSUMER_BUILD_DIR}" --config Release)

set(programs consumer consumer_fftw consumer_native)
if(GRANULE_MPI)
  list(APPEND programs consumer_mpi)  # an MPI program run as one process (a singleton)
endif()
foreach(program IN LISTS programs)
  find_program(exe_${program} ${program} PATHS "${CONSUMER_BUILD_DIR}" "${CONSUMER_BUILD_DIR}/Release"
               NO_DEFAULT_PATH REQUIRED)
  run_step("run ${program}" "${exe_${program}}")
endforeach()

if(DEFINED GRANULE_SOURCE_DIR AND NOT GRANULE_SOURCE_DIR STREQUAL "")
  run_step("configure a project that adds granule with add_subdirectory"
    "${CMAKE_COMMAND}" -S "${CONSUMER_SOURCE_DIR}/subdirectory" -B "${sub_build}" -G "${GENERATOR}"
    "-DGRANULE_SOURCE_DIR=${GRANULE_SOURCE_DIR}" "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
    -DCMAKE_BUILD_TYPE=Release)
  run_step("build it" "${CMAKE_COMMAND}" --build "${sub_build}" --config Release)
  run_step("install it into ${sub_prefix}"
    "${CMAKE_COMMAND}" --install "${sub_build}" --prefix "${sub_prefix}" --config Release)
  file(GLOB_RECURSE installed RELATIVE "${sub_prefix}" "${sub_prefix}/*")
  if(NOT installed MATCHES "consumer")
    message(FATAL_ERROR "install test: the parent's program was not installed: ${installed}")
  endif()
  if(installed MATCHES "granule")
    message(FATAL_ERROR "install test: add_subdirectory(granule) installed granule's files: ${installed}")
  endif()
endif()
