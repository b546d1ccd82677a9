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
# A file the consumer wrote through the Khronos validator (when it is there): 0 errors, 0 warnings.
function(validate name)
  if(GLTF_VALIDATOR)
    run(node ${GLTF_VALIDATOR} ${CONSUMER_DIR}/${name})
    if(NOT last_output MATCHES "\"numErrors\":0,\"numWarnings\":0")
      message(FATAL_ERROR "${name} is not valid glTF:\n${last_output}")
    endif()
  endif()
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX})
# The API reference, when the tree builds it (LIBWAVE_BUILD_DOCS): installed with the rest.
if(REFERENCE)
  if(NOT EXISTS ${PREFIX}/${REFERENCE})
    message(FATAL_ERROR "the API reference is not installed: no ${PREFIX}/${REFERENCE}")
  endif()
  file(READ ${PREFIX}/${REFERENCE} page)
  if(NOT page MATCHES "libwave API reference")
    message(FATAL_ERROR "${PREFIX}/${REFERENCE} is not the API reference's main page")
  endif()
  message(STATUS "API reference installed: ${PREFIX}/${REFERENCE}")
endif()
run(${CMAKE_COMMAND} -S ${EXAMPLES_SRC} -B ${CONSUMER_DIR} -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${PREFIX} -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${CONSUMER_DIR})
run(${CONSUMER_DIR}/dispersion_table)
if(NOT last_output MATCHES "0\\.7093")
  message(FATAL_ERROR "dispersion_table printed an unexpected table:\n${last_output}")
endif()
message(STATUS "installed libwave consumed by examples/:\n${last_output}")
# A consumer of the core component alone links none of the other components' heavy
# dependencies: no GDAL, Embree, Draco or OpenSubdiv in its ldd (a static build links
# what core uses; a shared one loads libwave_core.so and what it needs).
run(ldd ${CONSUMER_DIR}/dispersion_table)
foreach(heavy gdal embree draco osd wave_io wave_export wave_preview wave_refine wave_scene)
  if(last_output MATCHES "lib${heavy}")
    message(FATAL_ERROR "dispersion_table (libwave::core only) loads lib${heavy}:\n${last_output}")
  endif()
endforeach()
string(REGEX MATCHALL "\n" lines "${last_output}")
list(LENGTH lines ldd_count)
message(STATUS "libwave::core consumer: ${ldd_count} shared libraries, none of GDAL, Embree, Draco, OpenSubdiv")
# examples/pipeline.cpp: the Okushiri grid through every stage to one frame, equal bit for
# bit to the scene pipeline's (it exits 1 otherwise); the frame through the validator.
run(${CONSUMER_DIR}/pipeline ${DATA_DIR}/bathymetry/okushiri_monai_lab1to400_1p4cm.asc ${CONSUMER_DIR}/frame3.glb 3)
if(NOT last_output MATCHES "bit for bit")
  message(FATAL_ERROR "pipeline did not compare its frame:\n${last_output}")
endif()
message(STATUS "examples/pipeline.cpp:\n${last_output}")
validate(frame3.glb)
# examples/raw_grid.cpp: a seafloor from an array in memory (no reader, no GDAL: core and
# export), its isobaths where the plane's are, 12 frames as one animated .glb.
run(${CONSUMER_DIR}/raw_grid ${CONSUMER_DIR}/raw_grid.glb)
message(STATUS "examples/raw_grid.cpp:\n${last_output}")
run(ldd ${CONSUMER_DIR}/raw_grid)
if(last_output MATCHES "libgdal|libwave_io")
  message(FATAL_ERROR "raw_grid (libwave::export) loads GDAL or libwave_io:\n${last_output}")
endif()
validate(raw_grid.glb)
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
