# Registers a GoogleTest program's tests with CTest one suite at a time (napkin_add_tests in
# cmake/NapkinHelpers.cmake): run after the program is linked, it lists the program's tests
# (--gtest_list_tests) and writes OUT, a CTest file with one test "<PREFIX><Suite>" per suite that
# runs the program with --gtest_filter=<Suite>.*, so GoogleTest's output names the failing test.
#
# One process per suite rather than per test: the sanitized test programs are 40-115 MB and a start
# costs a quarter of a second of processor time, which over ~800 tests was minutes of `make test`.
# A suite's COST is its number of tests, so that CTest starts the big suites first (with no timing
# from an earlier run, it orders by COST) and a long suite does not end the run alone.
#
#   cmake -DEXE=<program> -DPREFIX=<folder/> -DOUT=<file> -DENVIRONMENT=<VAR=value> -P gtest_suites.cmake
execute_process(COMMAND "${EXE}" --gtest_list_tests OUTPUT_VARIABLE listing ERROR_VARIABLE errors
                RESULT_VARIABLE status TIMEOUT 60)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${EXE} --gtest_list_tests failed (${status}): ${errors}")
endif()
# The listing: "Suite." lines (a parameterised or typed suite: "Prefix/Suite." or "Suite/0.", maybe
# followed by "  # TypeParam = ..."), each followed by its tests indented by two spaces.
string(REPLACE ";" "\\;" listing "${listing}")
string(REPLACE "\n" ";" lines "${listing}")
set(suites "")
foreach(line IN LISTS lines)
  if(line MATCHES "^([^ #][^ ]*)\\.")
    set(suite "${CMAKE_MATCH_1}")
    list(APPEND suites "${suite}")
    set(count_${suite} 0)
  elseif(line MATCHES "^  [^ ]" AND DEFINED suite)
    math(EXPR count_${suite} "${count_${suite}} + 1")
  endif()
endforeach()
if(NOT suites)
  message(FATAL_ERROR "${EXE} --gtest_list_tests listed no test")
endif()
set(content "# Written by cmake/gtest_suites.cmake from ${EXE} --gtest_list_tests.\n")
foreach(suite IN LISTS suites)
  set(name "${PREFIX}${suite}")
  string(APPEND content
         "add_test([==[${name}]==] [==[${EXE}]==] [==[--gtest_filter=${suite}.*]==])\n"
         "set_tests_properties([==[${name}]==] PROPERTIES ENVIRONMENT [==[${ENVIRONMENT}]==] "
         "COST ${count_${suite}})\n")
endforeach()
file(WRITE "${OUT}" "${content}")
