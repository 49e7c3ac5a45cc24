# A second run of a whole GoogleTest executable under another environment (another GL driver,
# GL names reused as soon as freed). ctest runs it beside the discovered single tests of the same
# executable, so it gets its own TEST_TMPDIR (GoogleTest's TempDir() reads it): two runs of one
# test never write the same files at once. LABELS name what the run is for; the sanitized run
# (scripts/sanitize.sh) leaves out the labels it adds nothing to: "gl_names_reused" (lixel's code
# runs the same; only the uninstrumented driver's names differ) and "sweep" (one report over tens
# of seeded scenes, run whole in the Release suite).
function(lixel_add_whole_suite_test)
    cmake_parse_arguments(ARG "" "NAME;COMMAND;TIMEOUT" "ENVIRONMENT;LABELS" ${ARGN})
    set(tmp "${CMAKE_CURRENT_BINARY_DIR}/${ARG_NAME}.tmp")
    file(MAKE_DIRECTORY "${tmp}")
    add_test(NAME ${ARG_NAME} COMMAND ${ARG_COMMAND})
    set_tests_properties(${ARG_NAME} PROPERTIES
                         ENVIRONMENT "${ARG_ENVIRONMENT};TEST_TMPDIR=${tmp}"
                         TIMEOUT ${ARG_TIMEOUT})
    if(ARG_LABELS)
        set_tests_properties(${ARG_NAME} PROPERTIES LABELS "${ARG_LABELS}")
    endif()
endfunction()
