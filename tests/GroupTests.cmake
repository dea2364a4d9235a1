# Runs at build time (a POST_BUILD step of each test binary, tests/CMakeLists.txt): lists the
# binary's Google Tests per tier and writes the ctest file that runs them a group per process.
#
# A group is consecutive tests of one suite, at most GROUP_SIZE of them (a suite per process
# where it is small). Every test in its own process cost 0.6 s of start-up apiece (the dynamic
# loader binding the 264 libraries OpenImageIO brings, now only in clpt_io_tests) plus PoCL's start and a program load per
# integrator; a group pays those once and reuses the OpenCL context and its programs
# (docs/TESTING.md has the figures).
#
# Inputs (-D): TEST_EXECUTABLE, TIERS_FILE (sets CLPT_TIERS, and CLPT_TIER_FILTER_<tier> and
# CLPT_TIER_GROUP_<tier> (tests per group) and CLPT_TIER_COST_<tier> (ctest COST per test,
# which orders a run without timing history: costliest first) for each), CACHE_DIR (the tests' XDG_CACHE_HOME), OUT_FILE.
#
# OTHER_GROUPS (optional): the ctest file another test binary wrote. A group name found there
# too (a suite with tests in both binaries) stops the build: ctest would keep one of the two.
cmake_minimum_required(VERSION 3.20)
include("${TIERS_FILE}")
set(other_names "")
if(DEFINED OTHER_GROUPS AND EXISTS "${OTHER_GROUPS}")
  file(STRINGS "${OTHER_GROUPS}" other_lines REGEX "^add_test\\(\\[==\\[")
  foreach(l IN LISTS other_lines)
    if(l MATCHES "^add_test\\(\\[==\\[([^]]*)\\]==\\]")
      list(APPEND other_names "${CMAKE_MATCH_1}")
    endif()
  endforeach()
endif()

set(script "")
set(names "")
set(total 0)
foreach(tier IN LISTS CLPT_TIERS)
  execute_process(
    COMMAND "${TEST_EXECUTABLE}" --gtest_list_tests "--gtest_filter=${CLPT_TIER_FILTER_${tier}}"
    OUTPUT_VARIABLE listing RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 60)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "GroupTests: ${TEST_EXECUTABLE} --gtest_list_tests failed (${rc}): ${err}")
  endif()
  string(REPLACE ";" "\\;" listing "${listing}")
  string(REPLACE "\n" ";" lines "${listing}")
  # Consecutive tests of one suite, GROUP_SIZE at most: the names of each group joined by ':'.
  set(suite "")
  set(group "")
  set(count 0)
  set(part 0)
  set(groups "")  # entries "name|filter|count"
  macro(close_group)
    if(count GREATER 0)
      math(EXPR part "${part} + 1")
      list(APPEND groups "${suite}|${group}|${count}|${part}")
      set(group "")
      set(count 0)
    endif()
  endmacro()
  foreach(line IN LISTS lines)
    if(line MATCHES "^([^ #][^ ]*)\\.( .*)?$")  # "Suite." (typed suites add a comment)
      close_group()
      set(suite "${CMAKE_MATCH_1}")
      set(part 0)
    elseif(line MATCHES "^  ([^ ]+)")  # "  Test" (value-parametrised tests add a comment)
      if(count EQUAL CLPT_TIER_GROUP_${tier})
        close_group()
      endif()
      if(count GREATER 0)
        string(APPEND group ":")
      endif()
      string(APPEND group "${suite}.${CMAKE_MATCH_1}")
      math(EXPR count "${count} + 1")
      math(EXPR total "${total} + 1")
    endif()
  endforeach()
  close_group()
  # A suite in one group is named as the suite; a split one as SUITE.partK. A suite whose
  # tests fall in two tiers gets the tier in its name too.
  foreach(entry IN LISTS groups)
    string(REPLACE "|" ";" fields "${entry}")
    list(GET fields 0 gsuite)
    list(GET fields 1 gfilter)
    list(GET fields 2 gcount)
    list(GET fields 3 gpart)
    set(name "${gsuite}")
    if(NOT gpart EQUAL 1 OR "${groups}" MATCHES "(^|;)${gsuite}\\|[^;]*\\|2(;|$)")
      set(name "${gsuite}.part${gpart}")
    endif()
    if(name IN_LIST names)
      set(name "${name}.${tier}")
    endif()
    if(name IN_LIST other_names)
      message(FATAL_ERROR "GroupTests: ${name} is in both test binaries (${OUT_FILE} and ${OTHER_GROUPS}): "
                          "suite ${gsuite} has tests in a source that includes OpenImageIO and in one that "
                          "does not (tests/CMakeLists.txt); keep a suite's tests in one binary")
    endif()
    list(APPEND names "${name}")
    math(EXPR cost "${gcount} * ${CLPT_TIER_COST_${tier}}")
    string(APPEND script
      "add_test([==[${name}]==] [==[${TEST_EXECUTABLE}]==] [==[--gtest_filter=${gfilter}]==])\n"
      "set_tests_properties([==[${name}]==] PROPERTIES LABELS ${tier} COST ${cost} TIMEOUT 1500"
      " ENVIRONMENT [==[XDG_CACHE_HOME=${CACHE_DIR}]==])\n")
  endforeach()
endforeach()
file(WRITE "${OUT_FILE}" "# Written by tests/GroupTests.cmake: ${total} tests\n${script}")
