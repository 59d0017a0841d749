# cmake -P run.cmake: builds and runs tests/consumer against plume both ways.
file(REMOVE_RECURSE ${WORK})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endfunction()
set(src ${PLUME_SOURCE}/tests/consumer)
# 1. add_subdirectory
run(${CMAKE_COMMAND} -S ${src} -B ${WORK}/subdir -G ${GENERATOR} -DPLUME_VIA=subdirectory -DPLUME_SOURCE=${PLUME_SOURCE})
run(${CMAKE_COMMAND} --build ${WORK}/subdir)
run(${WORK}/subdir/consumer)
# 2. install, then find_package
run(${CMAKE_COMMAND} --install ${PLUME_BUILD} --prefix ${WORK}/prefix)
run(${CMAKE_COMMAND} -S ${src} -B ${WORK}/package -G ${GENERATOR} -DPLUME_VIA=package -DCMAKE_PREFIX_PATH=${WORK}/prefix)
run(${CMAKE_COMMAND} --build ${WORK}/package)
run(${WORK}/package/consumer)
message(STATUS "consumer project built and ran through add_subdirectory and find_package")
