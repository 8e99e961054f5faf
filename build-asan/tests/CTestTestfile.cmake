# CMake generated Testfile for 
# Source directory: /work/wt/io/tests
# Build directory: /work/wt/io/build-asan/tests
# 
# This file includes the relevant testing commands required for 
# testing this directory and lists subdirectories to be tested as well.
include("/work/wt/io/build-asan/tests/test_cli[1]_include.cmake")
include("/work/wt/io/build-asan/tests/test_dynamics[1]_include.cmake")
include("/work/wt/io/build-asan/tests/test_io[1]_include.cmake")
include("/work/wt/io/build-asan/tests/test_math[1]_include.cmake")
include("/work/wt/io/build-asan/tests/test_shapes[1]_include.cmake")
include("/work/wt/io/build-asan/tests/test_world[1]_include.cmake")
