# Runs the default scene in the morph, quantised morph, nodes, quantised nodes, files,
# Draco files, meshopt files and meshopt nodes forms (6 fps to keep it short), then plays each through the Blender add-on
# (tests/blender_addon.py; Draco frames through libwave's module; the skirt of Draco and
# of quantised nodes a second primitive joined again).
file(REMOVE_RECURSE ${OUT})
foreach(form morph quant nodes quant-nodes files draco meshopt meshopt-nodes pc2)
  set(args --fps 6)
  if(form STREQUAL "draco")
    list(APPEND args --form files --draco)
  elseif(form STREQUAL "meshopt")
    list(APPEND args --form files --codec meshopt)  # decoded by the libwave module the zip carries
  elseif(form STREQUAL "meshopt-nodes")
    list(APPEND args --form nodes --codec meshopt)  # one file, its frames read by the FrameReader kept open
  elseif(form STREQUAL "morph")
    list(APPEND args --no-quantize)  # the default scene's morph file is quantised
  elseif(form STREQUAL "quant")
    list(APPEND args --quantize)
  elseif(form STREQUAL "quant-nodes")
    list(APPEND args --form nodes --quantize)
  elseif(form STREQUAL "pc2")
    list(APPEND args --form pc2)
  elseif(NOT form STREQUAL "morph")
    list(APPEND args --form ${form})  # floats: another form than morph drops the scene's quantisation
  endif()
  execute_process(COMMAND ${WAVE} run -o ${OUT}/${form} -q ${args} RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "wave run (${form}) failed: ${err}")
  endif()
  list(APPEND runs ${OUT}/${form})
endforeach()
# A 10 m pool under 1 s waves with /underwater: caustic maps and sunbeam volumes beside
# the animation (no far field: the check frames the maps' rectangle by the seafloor's extent).
file(WRITE ${OUT}/pool.json [=[{"seafloor": {"source": "pool.asc"}, "waves": [{"period": 1.0, "amplitude": 0.04, "direction": [0, 1]}],
 "trace": {"ray_spacing": 0.1}, "preview": {"sun": {"elevation_degrees": 60, "azimuth_degrees": 100}},
 "underwater": {"map_size": 64, "water_type": "clear-ocean", "sunbeams": {"voxels": [20, 20, 8]}}, "animation": {"fps": 10}, "outputs": {"color": true},
 "surface": {"far_field": false}}]=])
set(pool "ncols 11\nnrows 11\nxllcorner 0\nyllcorner 0\ncellsize 1\n")
foreach(row RANGE 10)
  math(EXPR tenths "30 + 3 * (10 - ${row})")  # 3 m deep at y = 0 to 6 m at y = 10 (the first row is the top)
  math(EXPR whole "${tenths} / 10")
  math(EXPR frac "${tenths} % 10")
  string(REPEAT "-${whole}.${frac} " 11 line)
  string(APPEND pool "${line}\n")
endforeach()
file(WRITE ${OUT}/pool.asc "${pool}")
execute_process(COMMAND ${WAVE} run ${OUT}/pool.json -o ${OUT}/caustics -q RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "wave run (caustics) failed: ${err}")
endif()
list(APPEND runs ${OUT}/caustics)
execute_process(COMMAND ${BLENDER} -b --factory-startup --python-exit-code 1 --python ${SCRIPT} -- ${ADDON} ${runs}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "LIBWAVE-ADDON ok")
  message(FATAL_ERROR "The Blender add-on test failed (${rc}):\n${out}\n${err}")
endif()

# Baked into the .blend (the quantised default run): saved by a Blender with the add-on,
# played by a factory-settings Blender without it (tests/blender_bake.py).
get_filename_component(tests ${SCRIPT} DIRECTORY)
foreach(step save check)
  if(step STREQUAL "save")
    set(step_args save ${ADDON} ${OUT}/quant/animation.glb ${OUT}/baked.blend)
  else()
    set(step_args check ${OUT}/baked.blend ${OUT}/quant/animation.glb)
  endif()
  execute_process(COMMAND ${BLENDER} -b --factory-startup --python-exit-code 1 --python ${tests}/blender_bake.py -- ${step_args}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${out}")
  if(NOT rc EQUAL 0 OR NOT out MATCHES "LIBWAVE-BAKE ok")
    message(FATAL_ERROR "The baked .blend (${step}) failed (${rc}):\n${out}\n${err}")
  endif()
endforeach()

# The zip alone, with no PYTHONPATH (an artist's install): its own libwave module decodes
# the meshopt files form.
get_filename_component(bundled_tests ${SCRIPT} DIRECTORY)
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONPATH
                        ${BLENDER} -b --factory-startup --python-exit-code 1 --python ${bundled_tests}/blender_addon_bundled.py
                        -- ${ADDON} ${OUT}/meshopt/index.json 36
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "LIBWAVE-BUNDLED ok")
  message(FATAL_ERROR "The add-on's own libwave module (no PYTHONPATH) failed (${rc}):\n${out}\n${err}")
endif()
