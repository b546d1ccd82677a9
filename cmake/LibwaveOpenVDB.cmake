# OpenVDB (Debian's libopenvdb-dev): it ships Find modules, not a CMake config, and its
# headers need Imath's half at link time, so the header and both shared libraries are
# found directly and wrapped in an imported target. Included by the build and by
# libwaveConfig.cmake.
if(NOT TARGET libwave::openvdb)
  find_path(LIBWAVE_OPENVDB_INCLUDE_DIR openvdb/openvdb.h REQUIRED)
  find_library(LIBWAVE_OPENVDB_LIBRARY openvdb REQUIRED)
  find_library(LIBWAVE_IMATH_LIBRARY NAMES Imath Imath-3_1 REQUIRED)
  find_package(TBB 2021 CONFIG REQUIRED)
  add_library(libwave::openvdb UNKNOWN IMPORTED)
  set_target_properties(libwave::openvdb PROPERTIES
    IMPORTED_LOCATION "${LIBWAVE_OPENVDB_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${LIBWAVE_OPENVDB_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${LIBWAVE_IMATH_LIBRARY};TBB::tbb")
endif()
