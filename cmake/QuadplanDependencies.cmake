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

# The window front end: GLFW 3.3 and Dear ImGui 1.86, found through pkg-config. Debian ships
# ImGui as a static libimgui.a with the GLFW and Vulkan backends compiled in; its backend
# headers live in a subdirectory pkg-config does not name, and the link order matters.
find_package(PkgConfig REQUIRED)
pkg_check_modules(GLFW3 REQUIRED IMPORTED_TARGET glfw3)
pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)
find_path(IMGUI_BACKENDS_DIR NAMES imgui_impl_vulkan.h HINTS ${IMGUI_INCLUDE_DIRS} PATH_SUFFIXES backends REQUIRED)
find_package(Vulkan REQUIRED)
add_library(quadplan_imgui INTERFACE)
target_include_directories(quadplan_imgui INTERFACE ${IMGUI_INCLUDE_DIRS} ${IMGUI_BACKENDS_DIR})
target_link_libraries(quadplan_imgui INTERFACE PkgConfig::IMGUI PkgConfig::GLFW3 Vulkan::Vulkan)

# Exporting limit surfaces (export/): glTF through tinygltf, index order through meshoptimizer.
find_package(TinyGLTF REQUIRED)
find_package(meshoptimizer REQUIRED)
# Baking displacement maps (export/displacement_bake.h).
find_package(OpenEXR 3 REQUIRED CONFIG)
