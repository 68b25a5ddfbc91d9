# Finds every third-party dependency and exposes it as an imported target.
# Debian 12's OpenSubdivConfig.cmake names static libraries that are not shipped,
# so OpenSubdiv is located by hand (see docs/build.md).

find_package(Threads REQUIRED)
find_package(TBB REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(glm REQUIRED)

find_library(OSD_CPU_LIBRARY NAMES osdCPU REQUIRED)
find_path(OSD_INCLUDE_DIR NAMES opensubdiv/far/topologyRefiner.h REQUIRED)
add_library(OpenSubdiv::osdCpu SHARED IMPORTED)
set_target_properties(OpenSubdiv::osdCpu PROPERTIES
  IMPORTED_LOCATION ${OSD_CPU_LIBRARY}
  INTERFACE_INCLUDE_DIRECTORIES ${OSD_INCLUDE_DIR})

if(BUILD_TESTING OR NOT DEFINED BUILD_TESTING)
  find_package(GTest REQUIRED)
endif()
