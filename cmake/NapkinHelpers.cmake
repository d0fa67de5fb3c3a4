# Helpers in the spirit of COLMAP's CMakeHelper: one library per folder, one
# test executable per folder, tests registered with CTest as "<folder>/<Suite>".

set(NAPKIN_WARNING_FLAGS -Wall -Wextra -Wpedantic)
# Compile options for the test code only (tests/: the GoogleTest files and their support), after
# the build type's: `make test` compiles the test files with -O0 and napkin itself with -Og (its
# numeric libraries -O1, below; all with line tables for the sanitizers' reports). Test files are
# mostly GoogleTest's macros, whose optimised code costs most of a sanitizer build's time and buys
# nothing; the numerics they call stay optimised in napkin's libraries.
set(NAPKIN_TEST_CODE_OPTIONS "" CACHE STRING "Extra compile options for the test code (e.g. -O0)")
# Compile options for the numeric libraries only (engine/, synth/), after the build type's: `make
# test` compiles napkin at -Og, GCC's level for the edit-compile-debug cycle (half the compile time
# of -O1 under the sanitizers), and these two at -O1, as the tests spend their time in them.
set(NAPKIN_NUMERIC_CODE_OPTIONS "" CACHE STRING "Extra compile options for engine/ and synth/ (e.g. -O1)")
if(NAPKIN_WERROR)
  list(APPEND NAPKIN_WARNING_FLAGS -Werror)
endif()
# The sanitizers' compile options: napkin's code (every library, the program, the Python module)
# is instrumented; tests/CMakeLists.txt keeps only the address sanitizer for the test code (it says why).
set(NAPKIN_SANITIZE_COMPILE_OPTIONS -fsanitize=address,undefined -fno-omit-frame-pointer
                                    -fno-sanitize-recover=undefined)
# The address sanitizer's options of every file of the test build, test code included.
set(NAPKIN_ADDRESS_SANITIZER_OPTIONS -fsanitize=address -fno-omit-frame-pointer)
if(NAPKIN_SANITIZE AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  # No red zones around global variables (--param=asan-globals=0). GCC gives one to every record
  # the undefined-behaviour checks keep (their source locations and types: 191,000 of the napkin
  # program's 198,000 globals; ASAN_OPTIONS=report_globals=2 lists them). Each start registered
  # them all and the leak check scanned their 25 MB at exit: a quarter of the time of each of the
  # some 2,300 napkin processes the CLI tests start (178 -> 130 ms for `napkin --version`). What
  # the red zones caught, an index past the end of a global table, the checks below still catch:
  # the bounds check (-fsanitize=bounds, part of undefined) on arrays, libstdc++'s assertions on
  # std::array, std::span, std::vector and std::string_view.
  list(APPEND NAPKIN_SANITIZE_COMPILE_OPTIONS --param=asan-globals=0)
  list(APPEND NAPKIN_ADDRESS_SANITIZER_OPTIONS --param=asan-globals=0)
endif()
if(NAPKIN_SANITIZE)
  add_compile_options(${NAPKIN_SANITIZE_COMPILE_OPTIONS})
  add_link_options(-fsanitize=address,undefined)
  # libstdc++'s precondition checks (operator[] in range, front() of a non-empty container, ...),
  # in napkin's code and the tests' alike.
  add_compile_definitions(_GLIBCXX_ASSERTIONS)
  # The test build's programs start thousands of times (each GoogleTest suite is a process of its
  # own; the CLI tests run napkin once a case or more). Position-dependent, they start in half the time:
  # the dynamic loader no longer relocates every pointer of a 100+ MB sanitized program, which was
  # half of a start (perf: _dl_relocate_object). The objects stay -fPIE (Debian's default), so
  # the libraries still link into the Python module; the Release build's programs stay PIE.
  add_link_options("$<$<STREQUAL:$<TARGET_PROPERTY:TYPE>,EXECUTABLE>:-no-pie>")
endif()
if(NAPKIN_BUILD_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "NAPKIN_BUILD_FUZZ needs clang (libFuzzer): -DCMAKE_CXX_COMPILER=clang++")
  endif()
  # Every library carries libFuzzer's coverage instrumentation and the sanitizers; the fuzz
  # targets link libFuzzer's main (fuzz/CMakeLists.txt).
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# napkin_add_library(<name> [DEPS <targets>...] [PRIVATE_DEPS <targets>...]) :
# every *.cpp in the current folder. DEPS are the targets the folder's headers
# need (PUBLIC); PRIVATE_DEPS those only its sources use.
function(napkin_add_library name)
  cmake_parse_arguments(ARG "" "" "DEPS;PRIVATE_DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  add_library(${name} STATIC ${sources})
  set_target_properties(${name} PROPERTIES UNITY_BUILD ${NAPKIN_UNITY_BUILD} UNITY_BUILD_BATCH_SIZE 14)
  target_include_directories(${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_compile_options(${name} PRIVATE ${NAPKIN_WARNING_FLAGS})
  target_link_libraries(${name} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
endfunction()

# napkin_add_tests(<folder> [DEPS <targets>...]) : tests/<folder>/*.cpp into one
# GoogleTest executable, each of its suites registered with CTest as "<folder>/<Suite>".
function(napkin_add_tests folder)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${folder}/*.cpp)
  set(exe napkin_${folder}_tests)
  add_executable(${exe} ${sources})
  set_target_properties(${exe} PROPERTIES UNITY_BUILD ${NAPKIN_UNITY_BUILD} UNITY_BUILD_BATCH_SIZE 14)
  target_compile_options(${exe} PRIVATE ${NAPKIN_WARNING_FLAGS} ${NAPKIN_TEST_CODE_OPTIONS})
  target_link_libraries(${exe} PRIVATE ${ARG_DEPS} napkin_test_support GTest::gtest GTest::gmock GTest::gtest_main)
  # One CTest test per GoogleTest suite, listed from the program once it is linked
  # (cmake/gtest_suites.cmake says why); a program not built yet is one failing test that says so.
  set(suites_file "${CMAKE_CURRENT_BINARY_DIR}/${exe}_suites.cmake")
  add_custom_command(
    TARGET ${exe} POST_BUILD
    COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:${exe}> -DPREFIX=${folder}/ -DOUT=${suites_file}
            -DENVIRONMENT=NAPKIN_CONFIG_DIR=${PROJECT_SOURCE_DIR}/config -P ${PROJECT_SOURCE_DIR}/cmake/gtest_suites.cmake
    BYPRODUCTS ${suites_file}
    VERBATIM)
  set(include_file "${CMAKE_CURRENT_BINARY_DIR}/${exe}_include.cmake")
  file(WRITE "${include_file}"
       "if(EXISTS [==[${suites_file}]==])\n"
       "  include([==[${suites_file}]==])\n"
       "else()\n"
       "  add_test([==[${folder}/NOT_BUILT]==] [==[${exe}]==] was not built)\n"
       "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${include_file}")
endfunction()

# napkin_embed_files(<output .inc> <comment> <file>...) : writes, at build time, the files' names and
# bytes as C++ initialisers (cmake/embed_files.cmake) into <output>, rebuilt when a file changes:
# the report's page files and dygraphs (formats/), the SQL migrations (schema/). The target
# napkin_<output's name> (e.g. napkin_embedded_migrations) writes the fragment alone: `make tidy`
# builds it so clang-tidy finds the include without building the project. The library that
# compiles the fragment must depend on that target (add_dependencies), so the two never run the
# command at once.
function(napkin_embed_files output comment)
  list(JOIN ARGN "|" file_list)
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${output} -DFILES=${file_list} -P ${PROJECT_SOURCE_DIR}/cmake/embed_files.cmake
    DEPENDS ${ARGN} ${PROJECT_SOURCE_DIR}/cmake/embed_files.cmake
    COMMENT "${comment}"
    VERBATIM)
  get_filename_component(name ${output} NAME_WE)
  add_custom_target(napkin_${name} DEPENDS ${output})
endfunction()

# napkin_linked_targets(<target> <out-var>) : every target <target> links, directly or through the
# libraries it links (their LINK_LIBRARIES and INTERFACE_LINK_LIBRARIES, followed to the end), as
# the pairs "library;through" flattened into <out-var> (the library and the target that links it).
function(napkin_linked_targets target out_var)
  set(pending ${target})
  set(seen "")
  set(linked "")
  while(pending)
    list(POP_FRONT pending current)
    if(current IN_LIST seen OR NOT TARGET ${current})
      continue()
    endif()
    list(APPEND seen ${current})
    get_target_property(aliased ${current} ALIASED_TARGET)
    if(aliased)
      list(APPEND pending ${aliased})
    endif()
    foreach(property LINK_LIBRARIES INTERFACE_LINK_LIBRARIES)
      get_target_property(libraries ${current} ${property})
      if(NOT libraries)
        continue()
      endif()
      foreach(library IN LISTS libraries)
        string(REGEX REPLACE "^\\$<LINK_ONLY:(.*)>$" "\\1" library "${library}")
        list(APPEND linked ${library} ${current})
        list(APPEND pending ${library})
      endforeach()
    endforeach()
  endwhile()
  set(${out_var} ${linked} PARENT_SCOPE)
endfunction()

# napkin_check_not_linked(<target> FORBIDDEN <targets>... [REQUIRED <targets>...]) : stops the
# configuration with an error when <target> links any of the FORBIDDEN targets, directly or through
# the libraries it links (napkin_linked_targets), or does not link every REQUIRED one. The Python
# module, the fuzz targets and the app/ tests must not carry the command line (napkin_cli,
# CLI11): they link napkin_app. Called at the end of the top CMakeLists.txt, when every target
# exists.
function(napkin_check_not_linked target)
  cmake_parse_arguments(ARG "" "" "FORBIDDEN;REQUIRED" ${ARGN})
  napkin_linked_targets(${target} linked)
  set(found "")
  while(linked)
    list(POP_FRONT linked library current)
    if(library IN_LIST ARG_FORBIDDEN)
      message(FATAL_ERROR "${target} links ${library} (through ${current}); it must not: link napkin_app, "
                          "the application library, not the command line (docs/architecture.md).")
    endif()
    list(APPEND found ${library})
  endwhile()
  foreach(required IN LISTS ARG_REQUIRED)
    if(NOT required IN_LIST found)
      message(FATAL_ERROR "${target} does not link ${required}; it must (docs/architecture.md).")
    endif()
  endforeach()
endfunction()
