# Runs `wave run` on the default scene, then imports its animation.glb into Blender.
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${WAVE} run -o ${OUT} --json RESULT_VARIABLE rc OUTPUT_VARIABLE report ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "wave run failed: ${err}")
endif()
string(JSON frames GET "${report}" surface frames)
string(JSON vertices GET "${report}" surface vertices)
string(JSON fps GET "${report}" surface fps)
execute_process(COMMAND ${BLENDER} -b --factory-startup --python ${SCRIPT} -- ${OUT}/animation.glb ${fps} ${frames} ${vertices}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "BLENDER-IMPORT ok")
  message(FATAL_ERROR "Blender import failed (${rc}):\n${out}\n${err}")
endif()

# The nodes form (one object per frame), at 6 fps to keep the import short.
execute_process(COMMAND ${WAVE} run -o ${OUT}/nodes --form nodes --fps 6 --json RESULT_VARIABLE rc OUTPUT_VARIABLE report ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "wave run --form nodes failed: ${err}")
endif()
string(JSON frames GET "${report}" surface frames)
string(JSON vertices GET "${report}" surface vertices)
execute_process(COMMAND ${BLENDER} -b --factory-startup --python ${SCRIPT} -- ${OUT}/nodes/animation.glb 6 ${frames} ${vertices} nodes
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "BLENDER-IMPORT ok")
  message(FATAL_ERROR "Blender import of the nodes form failed (${rc}):\n${out}\n${err}")
endif()

# The plain float morph file (the default is quantised: KHR_mesh_quantization), at 6 fps.
execute_process(COMMAND ${WAVE} run -o ${OUT}/float --no-quantize --fps 6 --json RESULT_VARIABLE rc OUTPUT_VARIABLE report ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "wave run --no-quantize failed: ${err}")
endif()
string(JSON frames GET "${report}" surface frames)
string(JSON vertices GET "${report}" surface vertices)
execute_process(COMMAND ${BLENDER} -b --factory-startup --python ${SCRIPT} -- ${OUT}/float/animation.glb 6 ${frames} ${vertices}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "BLENDER-IMPORT ok")
  message(FATAL_ERROR "Blender import of the float morph file failed (${rc}):\n${out}\n${err}")
endif()
