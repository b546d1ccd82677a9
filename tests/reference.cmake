# The API reference builds with Doxygen without a single warning: every public symbol
# documented, no broken reference or bad command (docs/Doxyfile.in: WARN_AS_ERROR); and
# every public symbol the headers declare has a described page in it, which the warnings
# alone do not prove (tests/reference_coverage.py: Doxygen drops what an undocumented
# namespace or header holds without a warning). Both run; either fails the test.
execute_process(COMMAND ${DOXYGEN} ${DOCS_DIR}/Doxyfile WORKING_DIRECTORY ${DOCS_DIR}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
file(READ ${DOCS_DIR}/doxygen-warnings.log warnings)
string(STRIP "${warnings}${out}${err}" doxygen_said)
set(failed "")
if(NOT rc EQUAL 0 OR NOT warnings STREQUAL "")
  string(APPEND failed "doxygen failed (${rc}):\n${doxygen_said}\n")
endif()
if(NOT EXISTS ${DOCS_DIR}/reference/html/index.html)
  string(APPEND failed "no reference/html/index.html\n")
endif()
execute_process(COMMAND ${PYTHON} ${CMAKE_CURRENT_LIST_DIR}/reference_coverage.py ${DOXYGEN} ${DOCS_DIR}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  string(STRIP "${err}\n${out}" said)
  string(APPEND failed "reference_coverage.py failed (${rc}):\n${said}\n")
endif()
if(failed)
  message(FATAL_ERROR "${failed}")
endif()
message(STATUS "API reference built without warnings: ${DOCS_DIR}/reference/html/index.html\n${out}")
