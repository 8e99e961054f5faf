if(EXISTS "/work/wt/io/build-asan/tests/test_world")
  if(NOT EXISTS "/work/wt/io/build-asan/tests/test_world[1]_tests.cmake" OR
     NOT "/work/wt/io/build-asan/tests/test_world[1]_tests.cmake" IS_NEWER_THAN "/work/wt/io/build-asan/tests/test_world" OR
     NOT "/work/wt/io/build-asan/tests/test_world[1]_tests.cmake" IS_NEWER_THAN "${CMAKE_CURRENT_LIST_FILE}")
    include("/usr/share/cmake-3.25/Modules/GoogleTestAddTests.cmake")
    gtest_discover_tests_impl(
      TEST_EXECUTABLE [==[/work/wt/io/build-asan/tests/test_world]==]
      TEST_EXECUTOR [==[]==]
      TEST_WORKING_DIR [==[/work/wt/io/build-asan/tests]==]
      TEST_EXTRA_ARGS [==[]==]
      TEST_PROPERTIES [==[ENVIRONMENT;FULCRUM_SOURCE_DIR=/work/wt/io]==]
      TEST_PREFIX [==[]==]
      TEST_SUFFIX [==[]==]
      TEST_FILTER [==[]==]
      NO_PRETTY_TYPES [==[FALSE]==]
      NO_PRETTY_VALUES [==[FALSE]==]
      TEST_LIST [==[test_world_TESTS]==]
      CTEST_FILE [==[/work/wt/io/build-asan/tests/test_world[1]_tests.cmake]==]
      TEST_DISCOVERY_TIMEOUT [==[60]==]
      TEST_XML_OUTPUT_DIR [==[]==]
    )
  endif()
  include("/work/wt/io/build-asan/tests/test_world[1]_tests.cmake")
else()
  add_test(test_world_NOT_BUILT test_world_NOT_BUILT)
endif()
