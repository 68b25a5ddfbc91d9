# Smoke tests of the command line as a user types it. Detailed checks of the output live in
# test_cli.cpp, which runs the same binary and parses what it prints.
add_test(NAME cli.help COMMAND quadplan --help)
set_tests_properties(cli.help PROPERTIES PASS_REGULAR_EXPRESSION "info.*edit|edit.*info")

add_test(NAME cli.info_missing_file COMMAND quadplan info ${CMAKE_CURRENT_SOURCE_DIR}/data/does-not-exist.obj)
set_tests_properties(cli.info_missing_file PROPERTIES WILL_FAIL TRUE)

add_test(NAME cli.info_default_scene COMMAND quadplan info --json ${CMAKE_SOURCE_DIR}/scenes/default.json)
set_tests_properties(cli.info_default_scene PROPERTIES PASS_REGULAR_EXPRESSION "\"faces\"")
