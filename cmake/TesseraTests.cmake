# tessera_unit_tests(TARGET SHARDS N [PROPERTIES prop value ...])
#
# Registers a GoogleTest binary of many short tests with ctest.
#
# By default each gtest test is its own ctest test (gtest_discover_tests), so `ctest -R Name`
# runs one. With -DTESSERA_TEST_SHARDS=ON (scripts/test.sh's sanitizer build) the binary is
# registered as N ctest tests instead, `TARGET.shard-I-of-N`, each running every N-th test in one
# process through GoogleTest's own sharding (GTEST_TOTAL_SHARDS / GTEST_SHARD_INDEX). Why: a
# process that links OpenImageIO spends about 0.45 s in the dynamic loader before main (about
# 260 libraries; 0.7 s under the sanitizers), which was most of the time of the sanitizer pass's
# 900 short tests. A failing shard's output names the failing test; run it alone with
# `bin/TARGET --gtest_filter=Suite.Name`.
#
# Only binaries whose tests are independent of one another in one process belong here (every
# GoogleTest binary should be; the end-to-end and fault suites keep one process per test because
# each of their tests is long and starts its own servers).
option(TESSERA_TEST_SHARDS "Run each unit-test binary as a few shards instead of a process per test" OFF)
include(GoogleTest)
function(tessera_unit_tests target)
  cmake_parse_arguments(ARG "" "SHARDS" "PROPERTIES" ${ARGN})
  if(NOT ARG_SHARDS)
    set(ARG_SHARDS 1)
  endif()
  if(TESSERA_TEST_SHARDS)
    math(EXPR last "${ARG_SHARDS} - 1")
    foreach(i RANGE ${last})
      set(name "${target}.shard-${i}-of-${ARG_SHARDS}")
      add_test(NAME ${name} COMMAND $<TARGET_FILE:${target}>)
      set_tests_properties(${name} PROPERTIES
        ENVIRONMENT "GTEST_TOTAL_SHARDS=${ARG_SHARDS};GTEST_SHARD_INDEX=${i}" ${ARG_PROPERTIES})
    endforeach()
  else()
    gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60 PROPERTIES ${ARG_PROPERTIES})
  endif()
endfunction()
