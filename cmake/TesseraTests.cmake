# How the GoogleTest binaries the sanitizer pass runs (every test not labelled slow, faults or
# load: "the short suites") are registered with ctest.
#
# tessera_unit_tests(TARGET [SHARDS N] [PROPERTIES prop value ...])
#   A binary of many short tests. By default each gtest test is its own ctest test
#   (gtest_discover_tests), so `ctest -R Name` runs one. With -DTESSERA_TEST_SHARDS=ON
#   (scripts/test.sh's sanitizer build) the binary is registered as N ctest tests instead,
#   `TARGET.shard-I-of-N`, each running every N-th test in one process through GoogleTest's own
#   sharding (GTEST_TOTAL_SHARDS / GTEST_SHARD_INDEX). Why: a process that links OpenImageIO
#   spends about 0.45 s in the dynamic loader before main (about 260 libraries; 0.7 s under the
#   sanitizers), which was most of the time of the sanitizer pass's 900 short tests. A failing
#   shard's output names the failing test; run it alone with `bin/TARGET --gtest_filter=Suite.Name`.
#   Every binary registered here passes run whole in one process.
#
# tessera_e2e_tests(TARGET [PROPERTIES prop value ...])
#   A binary of long tests that each start their own servers and processes: always a ctest test
#   per gtest test.
#
# With -DTESSERA_BUILD_SHORT_SUITES=OFF (scripts/test.sh's release build, which runs only the long
# suites) both leave TARGET out of `all` and register nothing; `ninja TARGET` still builds it.
option(TESSERA_TEST_SHARDS "Run each unit-test binary as a few shards instead of a process per test" OFF)
option(TESSERA_BUILD_SHORT_SUITES "Build the test binaries not labelled slow, faults or load" ON)
option(TESSERA_UNITY_TESTS "Compile each test binary's sources a few files per translation unit" OFF)
include(GoogleTest)

# With -DTESSERA_UNITY_TESTS=ON (scripts/test.sh's sanitizer build) a unit-test binary's sources are
# compiled UNITY_BATCH files to a translation unit (CMake's unity build), so the headers every
# test file includes (GoogleTest, the scene and render headers) are parsed and instantiated once
# per batch instead of once per file. The test files keep their helpers in anonymous namespaces
# with names of their own, so that any of them can share a translation unit.
set(TESSERA_UNITY_BATCH 8 CACHE STRING "Test files per translation unit with TESSERA_UNITY_TESTS")
macro(_tessera_unity target)
  if(TESSERA_UNITY_TESTS)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON
                          UNITY_BUILD_BATCH_SIZE ${TESSERA_UNITY_BATCH})
  endif()
endmacro()

# Without the short suites: TARGET out of `all`, and the calling function returns (a macro's
# return() leaves its caller).
macro(_tessera_leave_out_unless_short_suites target)
  if(NOT TESSERA_BUILD_SHORT_SUITES)
    set_target_properties(${target} PROPERTIES EXCLUDE_FROM_ALL TRUE)
    return()
  endif()
endmacro()

function(tessera_unit_tests target)
  cmake_parse_arguments(ARG "" "SHARDS" "PROPERTIES" ${ARGN})
  _tessera_leave_out_unless_short_suites(${target})
  _tessera_unity(${target})
  if(NOT ARG_SHARDS)
    set(ARG_SHARDS 1)
  endif()
  if(TESSERA_TEST_SHARDS)
    math(EXPR last "${ARG_SHARDS} - 1")
    foreach(i RANGE ${last})
      set(name "${target}.shard-${i}-of-${ARG_SHARDS}")
      add_test(NAME ${name} COMMAND $<TARGET_FILE:${target}>)
      set_tests_properties(${name} PROPERTIES COST 50
        ENVIRONMENT "GTEST_TOTAL_SHARDS=${ARG_SHARDS};GTEST_SHARD_INDEX=${i}" ${ARG_PROPERTIES})
    endforeach()
  else()
    gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60 PROPERTIES ${ARG_PROPERTIES})
  endif()
endfunction()

function(tessera_e2e_tests target)
  cmake_parse_arguments(ARG "" "" "PROPERTIES" ${ARGN})
  _tessera_leave_out_unless_short_suites(${target})
  # COST: with no timings from an earlier run (CI's clean checkout), `ctest -j` starts the tests
  # of higher cost first, so these long ones do not come last and leave a core idle at the end.
  gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60 PROPERTIES COST 100 ${ARG_PROPERTIES})
endfunction()
