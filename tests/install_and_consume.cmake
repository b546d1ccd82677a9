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
# The installed Python module imports from the prefix (Debian's dist-packages layout).
if(PYTHON_MODULE_DIR)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${PREFIX}/${PYTHON_MODULE_DIR}
                    ${PYTHON} -c "import libwave; print('libwave', libwave.__version__, libwave.__file__)"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "${PREFIX}")
    message(FATAL_ERROR "import libwave from ${PREFIX}/${PYTHON_MODULE_DIR} failed (${rc}):\n${out}\n${err}")
  endif()
  message(STATUS "installed Python module: ${out}")
endif()
