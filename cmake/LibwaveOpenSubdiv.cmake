# OpenSubdiv (Debian's libosd-dev): its CMake config names a libosdCPU.a that is not
# shipped (docs/build-notes.md), so the header and the shared library are found directly and
# wrapped in an imported target. Included by the build and by libwaveConfig.cmake.
if(NOT TARGET libwave::opensubdiv)
  find_path(LIBWAVE_OSD_INCLUDE_DIR opensubdiv/far/topologyRefiner.h REQUIRED)
  find_library(LIBWAVE_OSD_LIBRARY osdCPU REQUIRED)
  add_library(libwave::opensubdiv UNKNOWN IMPORTED)
  set_target_properties(libwave::opensubdiv PROPERTIES
    IMPORTED_LOCATION "${LIBWAVE_OSD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${LIBWAVE_OSD_INCLUDE_DIR}")
endif()
