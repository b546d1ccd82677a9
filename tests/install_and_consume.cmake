# Installs the build tree into PREFIX, then builds examples/ as a separate project
# with find_package(libwave CONFIG REQUIRED) and runs the example program.
file(REMOVE_RECURSE ${PREFIX} ${CONSUMER_DIR})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX})
run(${CMAKE_COMMAND} -S ${EXAMPLES_SRC} -B ${CONSUMER_DIR} -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${PREFIX} -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${CONSUMER_DIR})
run(${CONSUMER_DIR}/dispersion_table)
if(NOT last_output MATCHES "0\\.7093")
  message(FATAL_ERROR "dispersion_table printed an unexpected table:\n${last_output}")
endif()
message(STATUS "installed libwave consumed by examples/:\n${last_output}")
