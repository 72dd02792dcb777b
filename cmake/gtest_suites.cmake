# Registers a GoogleTest binary's cases with CTest one test suite per entry (included by CTest
# through TEST_INCLUDE_FILES, so the list comes from the binary as built: `--gtest_list_tests`).
#
# Why suites and not cases: every process compiles its Vulkan kernels again (lavapipe's
# pipeline cache keeps nothing), and the renderers' kernels take seconds each; one process per
# suite compiles them once for all its cases and shares the test scene cache, which halves the
# suite's time (the 16 cases of stat.PmcHiTest: 40 s as 16 processes, 18 s as one).
#
# Two tiers (README "Tests"): a case whose full name (Prefix/Suite.Case/N) matches one of
# FULL_TESTS' patterns for this binary ("LABEL:pattern", `*` any characters) runs in the entry
# `LABEL.Prefix/Suite.full`, labelled `full`; the others run in `LABEL.Prefix/Suite`.
# `cmake --build build --target check` runs every entry without the label, `check-full` all.
#
# COSTS ("entry=seconds", measured) orders the first run of a fresh build directory, as CI's
# is: ctest starts the longest entries first when it has no timings of its own yet, so that no
# long entry starts last and runs alone on one of the two cores.
#
#   pmcr_add_gtest_suites(EXE exe LABEL label TIMEOUT s PROCESSORS n
#                         ENVIRONMENT env... FULL_TESTS patterns... COSTS costs...)
function(pmcr_add_gtest_suites)
    cmake_parse_arguments(arg "" "EXE;LABEL;TIMEOUT;PROCESSORS" "FULL_TESTS;ENVIRONMENT;COSTS" ${ARGN})
    # This binary's patterns, as regular expressions.
    set(patterns "")
    set(regexes "")
    foreach(entry IN LISTS arg_FULL_TESTS)
        if(entry MATCHES "^${arg_LABEL}:(.*)$")
            set(pattern "${CMAKE_MATCH_1}")
            string(REGEX REPLACE "([][.+?^$()|\\])" "\\\\\\1" regex "${pattern}")
            string(REPLACE "*" ".*" regex "${regex}")
            list(APPEND patterns "${pattern}")
            list(APPEND regexes "^${regex}$")
        endif()
    endforeach()
    if(NOT EXISTS "${arg_EXE}")
        # Not built yet: one entry that fails and says so, never a silently empty tier.
        add_test("${arg_LABEL}.NOT_BUILT" "${arg_EXE}")
        return()
    endif()
    execute_process(COMMAND "${arg_EXE}" --gtest_list_tests
                    OUTPUT_VARIABLE listing RESULT_VARIABLE rc TIMEOUT 60)
    if(NOT rc EQUAL 0)
        add_test("${arg_LABEL}.LIST_FAILED" "${arg_EXE}" --gtest_list_tests)
        return()
    endif()
    set(used_patterns "")
    string(REPLACE "\n" ";" lines "${listing}")
    set(suite "")
    set(check_cases "")
    set(full_cases "")
    foreach(line IN LISTS lines ITEMS "END.")  # END. flushes the last suite
        if(line MATCHES "^([^ ][^ ]*)\\.( .*)?$")  # "Prefix/Suite." starts the next suite
            if(suite)
                _pmcr_suite_entries("${suite}" "${check_cases}" "${full_cases}")
            endif()
            set(suite "${CMAKE_MATCH_1}")
            set(check_cases "")
            set(full_cases "")
        elseif(line MATCHES "^  ([^ ]+)")  # "  Case/N  # GetParam() = ..."
            set(name "${suite}.${CMAKE_MATCH_1}")
            set(full FALSE)
            set(i 0)
            foreach(regex IN LISTS regexes)
                if(name MATCHES "${regex}")
                    set(full TRUE)
                    list(GET patterns ${i} pattern)
                    list(APPEND used_patterns "${pattern}")
                endif()
                math(EXPR i "${i} + 1")
            endforeach()
            if(full)
                list(APPEND full_cases "${name}")
            else()
                list(APPEND check_cases "${name}")
            endif()
        endif()
    endforeach()
    # A pattern that matches no case (a renamed test) is a mistake in the tier list: an entry
    # that fails and names it.
    foreach(pattern IN LISTS patterns)
        list(FIND used_patterns "${pattern}" used)  # (no if(IN_LIST): CTest runs this with old policies)
        if(used EQUAL -1)
            # The binary with a filter that selects nothing, made to fail: ctest prints the name.
            add_test("${arg_LABEL}.UNKNOWN_FULL_TEST:${pattern}" "${arg_EXE}" "--gtest_filter=-*")
            set_tests_properties("${arg_LABEL}.UNKNOWN_FULL_TEST:${pattern}" PROPERTIES
                                 LABELS "${arg_LABEL}" WILL_FAIL TRUE)
        endif()
    endforeach()
endfunction()

# Adds `<suite>` (the cases not in the full tier) and `<suite>.full` (those in it).
macro(_pmcr_suite_entries suite check_cases full_cases)
    if(NOT "${check_cases}" STREQUAL "")
        set(_filter "${suite}.*")
        if(NOT "${full_cases}" STREQUAL "")
            string(REPLACE ";" ":" _excluded "${full_cases}")
            set(_filter "${suite}.*-${_excluded}")
        endif()
        _pmcr_add_entry("${suite}" "${_filter}" "${arg_LABEL}")
    endif()
    if(NOT "${full_cases}" STREQUAL "")
        string(REPLACE ";" ":" _filter "${full_cases}")
        _pmcr_add_entry("${suite}.full" "${_filter}" "${arg_LABEL};full")
    endif()
endmacro()

macro(_pmcr_add_entry name filter labels)
    add_test("${arg_LABEL}.${name}" "${arg_EXE}" "--gtest_filter=${filter}")
    set_tests_properties("${arg_LABEL}.${name}" PROPERTIES LABELS "${labels}" TIMEOUT "${arg_TIMEOUT}"
                         PROCESSORS "${arg_PROCESSORS}" ENVIRONMENT "${arg_ENVIRONMENT}")
    # (No regular expression here: the caller's CMAKE_MATCH_1 must survive this macro.)
    foreach(_cost IN LISTS arg_COSTS)
        string(FIND "${_cost}" "=" _at REVERSE)
        string(SUBSTRING "${_cost}" 0 ${_at} _entry)
        if(_entry STREQUAL "${arg_LABEL}.${name}")
            math(EXPR _at "${_at} + 1")
            string(SUBSTRING "${_cost}" ${_at} -1 _seconds)
            set_tests_properties("${arg_LABEL}.${name}" PROPERTIES COST "${_seconds}")
        endif()
    endforeach()
endmacro()
