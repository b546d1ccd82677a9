# The API reference builds with Doxygen without a single warning: every public symbol
# documented, no broken reference or bad command (docs/Doxyfile.in: WARN_AS_ERROR).
execute_process(COMMAND ${DOXYGEN} ${DOCS_DIR}/Doxyfile WORKING_DIRECTORY ${DOCS_DIR}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
file(READ ${DOCS_DIR}/doxygen-warnings.log warnings)
if(NOT rc EQUAL 0 OR NOT warnings STREQUAL "")
  message(FATAL_ERROR "doxygen failed (${rc}):\n${warnings}\n${out}\n${err}")
endif()
if(NOT EXISTS ${DOCS_DIR}/reference/html/index.html)
  message(FATAL_ERROR "no reference/html/index.html")
endif()
message(STATUS "API reference built without warnings: ${DOCS_DIR}/reference/html/index.html")
