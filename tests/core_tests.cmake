# The unit tests that need only the core (readers, topology, plans, edits, history,
# displacement, animation) as their own binary, quadplan_core_tests, for the core's sanitized
# build (QUADPLAN_FUZZ, top-level CMakeLists.txt). The same sources are in quadplan_tests too;
# here their tests are named sanitized.<Suite>.<Test>.
include(GoogleTest)
set(CORE_TEST_SOURCES displacement/brush displacement/brush_mask displacement/displacement displacement/displacement_io
    displacement/displaced_picking edit/edit_history plans/dense_stencils plans/edit_replanning mesh/generated_cage mesh/obj_io plans/patch_basis
    edit/picking plans/plan plans/plan_shapes scene/scene scene/scene_objects edit/selection mesh/topology
    mesh/topology_edits mesh/mesh_import animation/cage_sequence animation/cage_animation)
list(TRANSFORM CORE_TEST_SOURCES REPLACE "(.+)/(.+)" "${CMAKE_CURRENT_LIST_DIR}/\\1/test_\\2.cpp")
add_executable(quadplan_core_tests ${CORE_TEST_SOURCES})
target_include_directories(quadplan_core_tests PRIVATE ${CMAKE_CURRENT_LIST_DIR})
target_link_libraries(quadplan_core_tests PRIVATE quadplan_core GTest::gtest GTest::gtest_main)
target_compile_definitions(quadplan_core_tests PRIVATE
  QUADPLAN_TEST_DATA="${CMAKE_CURRENT_LIST_DIR}/data"
  QUADPLAN_SHARED_DIR="${CMAKE_SOURCE_DIR}/../shared"
  QUADPLAN_SCENES_DIR="${CMAKE_SOURCE_DIR}/scenes")
gtest_discover_tests(quadplan_core_tests TEST_PREFIX sanitized. DISCOVERY_TIMEOUT 60)
