# cmake -P run.cmake: builds and runs tests/consumer against plume both ways.
file(REMOVE_RECURSE ${WORK})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endfunction()
set(src ${PLUME_SOURCE}/tests/consumer)
# 1. add_subdirectory (not with -DPACKAGE_ONLY=ON: the dispatch build's test, whose
#    add_subdirectory path would be the scalar build's again)
if(NOT PACKAGE_ONLY)
  # Unoptimised: this path checks the CMake integration, not speed, and -O0 compiles plume's
  # sources in a fraction of -O3's time (docs/performance.md, "CI time").
  run(${CMAKE_COMMAND} -S ${src} -B ${WORK}/subdir -G ${GENERATOR} -DPLUME_VIA=subdirectory -DPLUME_SOURCE=${PLUME_SOURCE}
      -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-O0)
  run(${CMAKE_COMMAND} --build ${WORK}/subdir)
  run(${WORK}/subdir/consumer)
endif()
# 2. install, then find_package
run(${CMAKE_COMMAND} --install ${PLUME_BUILD} --prefix ${WORK}/prefix)
run(${CMAKE_COMMAND} -S ${src} -B ${WORK}/package -G ${GENERATOR} -DPLUME_VIA=package -DCMAKE_PREFIX_PATH=${WORK}/prefix)
run(${CMAKE_COMMAND} --build ${WORK}/package)
run(${WORK}/package/consumer)
if(EXISTS ${WORK}/package/consumer_shared)
  run(${WORK}/package/consumer_shared)
endif()
message(STATUS "consumer project built and ran through add_subdirectory and find_package")
