# Smoke tests of the command line as a user types it. Detailed checks of the output live in
# test_cli.cpp, which runs the same binary and parses what it prints.
add_test(NAME cli.help COMMAND quadplan --help)
set_tests_properties(cli.help PROPERTIES PASS_REGULAR_EXPRESSION "info.*edit|edit.*info")

add_test(NAME cli.info_missing_file COMMAND quadplan info ${CMAKE_CURRENT_SOURCE_DIR}/data/does-not-exist.obj)
set_tests_properties(cli.info_missing_file PROPERTIES WILL_FAIL TRUE)

add_test(NAME cli.info_default_scene COMMAND quadplan info --json ${CMAKE_SOURCE_DIR}/scenes/default.json)
set_tests_properties(cli.info_default_scene PROPERTIES PASS_REGULAR_EXPRESSION "\"faces\"")

# check-limit over every Catmull-Clark cage OpenSubdiv ships for its regression (../shared).
# Exclusions are listed with their reason in docs/plan-engine.md.
set(QP_SHARED_SHAPES ${CMAKE_SOURCE_DIR}/../shared/shapes)
set(QP_CHECK_LIMIT_EXCLUDED "")
if(IS_DIRECTORY ${QP_SHARED_SHAPES})
  file(GLOB QP_CATMARK_SHAPES ${QP_SHARED_SHAPES}/catmark_*.obj)
  foreach(shape ${QP_CATMARK_SHAPES})
    get_filename_component(name ${shape} NAME_WE)
    if(name IN_LIST QP_CHECK_LIMIT_EXCLUDED)
      continue()
    endif()
    add_test(NAME check_limit.${name} COMMAND quadplan check-limit ${shape})
  endforeach()
else()
  add_test(NAME check_limit.shared_shapes
           COMMAND ${CMAKE_COMMAND} -E echo "SKIPPED: ../shared/shapes is not beside the project")
  set_tests_properties(check_limit.shared_shapes PROPERTIES SKIP_REGULAR_EXPRESSION "SKIPPED")
endif()

# The benchmark's code path on tiny sizes, so CI exercises it in a few seconds.
add_test(NAME cli.bench_plans_smoke
         COMMAND quadplan bench plans --repeats 1 --generated-faces 2000 --no-shared)
set_tests_properties(cli.bench_plans_smoke PROPERTIES PASS_REGULAR_EXPRESSION "\\(d\\) evaluate" TIMEOUT 60)

# The render suite on a tiny cage at one factor: Vulkan (lavapipe), all four paths, the table.
add_test(NAME cli.bench_render_smoke
         COMMAND quadplan bench render --repeats 1 --generated-faces 500 --no-shared --factors 2)
set_tests_properties(cli.bench_render_smoke PROPERTIES PASS_REGULAR_EXPRESSION "\\| 2 \\| 2 \\| [0-9]+ \\|" TIMEOUT 60)

# The schemes suite on a tiny cage at one factor: every scheme plugin against pre-tessellated
# triangles; a row for a scheme with its ratio.
add_test(NAME cli.bench_schemes_smoke
         COMMAND quadplan bench schemes --repeats 1 --generated-faces 300 --no-shared --factors 2)
set_tests_properties(cli.bench_schemes_smoke PROPERTIES
                     PASS_REGULAR_EXPRESSION "\\| scheme [a-z0-9-]+, factor 2 \\([0-9?]+ triangles, [a-z?]+\\): frame [^|]+ triangles \\([0-9]+\\) \\| 1 \\| [0-9.]+ ms \\| [0-9.]+ ms \\| [0-9.]+ \\|"
                     TIMEOUT 60)

# The fas suite on a tiny cage at one factor: plans and osd-fas through their paths, the
# tess-against-tess row with both sides' primitives and triangles.
add_test(NAME cli.bench_fas_smoke
         COMMAND quadplan bench fas --repeats 1 --generated-faces 300 --no-shared --factors 4)
set_tests_properties(cli.bench_fas_smoke PROPERTIES
                     PASS_REGULAR_EXPRESSION "plans tess vs osd-fas tess, factor 4: moving frame \\([1-9][0-9]* vs [1-9][0-9]* primitives, [1-9][0-9]* vs [1-9][0-9]* triangles\\) \\| 1 \\| [0-9.]+ ms"
                     TIMEOUT 60)

# The scale suite on a small cage: planning cold and warm, the frames and the edits all report.
add_test(NAME cli.bench_scale_smoke
         COMMAND quadplan bench scale --repeats 1 --generated-faces 2000 --no-shared)
set_tests_properties(cli.bench_scale_smoke PROPERTIES
                     PASS_REGULAR_EXPRESSION "\\(b\\) warm plan[^|]*\\| 1 \\| [0-9.]+ ms.*\\(d\\) full-view frame[^|]*[1-9][0-9]* triangles, [0-9]+ of them covering no pixel centre[^|]*\\) \\| 3 \\| [0-9.]+ ms.*\\(g\\) crease an interior edge[^|]*\\| 3 \\| [0-9.]+ ms"
                     TIMEOUT 120)

# The macro suite on a small cage: the partitions against single faces, the regular torus too.
add_test(NAME cli.bench_macro_smoke
         COMMAND quadplan bench macro --repeats 1 --generated-faces 600 --no-shared)
set_tests_properties(cli.bench_macro_smoke PROPERTIES
                     PASS_REGULAR_EXPRESSION "regular torus[^|]*\\| [0-9]+ \\| per-face factor 1/4: blocks macro faces \\([0-9]+ triangles\\) vs single faces at factor 1 \\([0-9]+ triangles\\)"
                     TIMEOUT 120)
# A macro option the plans scheme does not know is an error that says what it takes.
add_test(NAME cli.render_bad_macro_option
         COMMAND quadplan render ${CMAKE_SOURCE_DIR}/scenes/default.json --size 64x48 --option macro=triangles
                 --out ${CMAKE_BINARY_DIR}/test-output/bad_macro_option.png)
set_tests_properties(cli.render_bad_macro_option PROPERTIES PASS_REGULAR_EXPRESSION "auto, rectangles, quartets, blocks or off")
add_test(NAME cli.render_bad_minify_option
         COMMAND quadplan render ${CMAKE_SOURCE_DIR}/scenes/default.json --size 64x48 --tess 1 --option minify=0
                 --out ${CMAKE_BINARY_DIR}/test-output/bad_minify_option.png)
set_tests_properties(cli.render_bad_minify_option PROPERTIES PASS_REGULAR_EXPRESSION "whole number from 1 to 64")

# Scheme plugins: the comparison of the built-in schemes on the default scene, as JSON.
file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/test-output)
add_test(NAME cli.compare_smoke
         COMMAND quadplan compare ${CMAKE_SOURCE_DIR}/scenes/default.json --schemes plans,osd-fas,uniform --json
                 --size 160x120 --tess 2 --samples 4 --repeats 1 --out ${CMAKE_BINARY_DIR}/test-output/compare_smoke.png)
set_tests_properties(cli.compare_smoke PROPERTIES PASS_REGULAR_EXPRESSION "\"max_rel_error\"" TIMEOUT 120)
add_test(NAME cli.schemes COMMAND quadplan schemes)
set_tests_properties(cli.schemes PROPERTIES PASS_REGULAR_EXPRESSION "osd-fas.*plans.*uniform")

# Headless sculpting as a script would run it (detailed checks in test_cli_sculpt.cpp).
add_test(NAME cli.sculpt_smoke
         COMMAND quadplan sculpt ${CMAKE_SOURCE_DIR}/scenes/creased_box.json --radius 0.5 --strength 0.1
                 --mirror x --path "0,1.2,0;0.5,1.2,0.5" --out ${CMAKE_CURRENT_BINARY_DIR}/sculpt_smoke.json)
set_tests_properties(cli.sculpt_smoke PROPERTIES PASS_REGULAR_EXPRESSION "sculpt: 1 stroke, [0-9]+ dabs, [1-9][0-9]* of")

# The displacement suite's code path on a small cage.
add_test(NAME cli.bench_displacement_smoke
         COMMAND quadplan bench displacement --repeats 1 --generated-faces 300 --no-shared)
set_tests_properties(cli.bench_displacement_smoke PROPERTIES PASS_REGULAR_EXPRESSION "raise dab, radius" TIMEOUT 60)
