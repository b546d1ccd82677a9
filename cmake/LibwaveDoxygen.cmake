# The API reference (the `docs` target): Doxygen on <build>/docs/Doxyfile, which writes its
# warnings to a log and fails on any (docs/Doxyfile.in); the log is shown when it fails.
# cmake -DDOXYGEN=<doxygen> -DDOCS_DIR=<build>/docs -P LibwaveDoxygen.cmake
execute_process(COMMAND ${DOXYGEN} ${DOCS_DIR}/Doxyfile WORKING_DIRECTORY ${DOCS_DIR}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  file(READ ${DOCS_DIR}/doxygen-warnings.log warnings)
  message(FATAL_ERROR "the API reference: Doxygen failed (${rc}); every public symbol of the headers needs a "
                      "Doxygen comment (docs/reference.md):\n${warnings}${out}${err}")
endif()
