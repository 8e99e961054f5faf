
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "/work/wt/io/tests/world/api_example_test.cpp" "tests/CMakeFiles/test_world.dir/world/api_example_test.cpp.o" "gcc" "tests/CMakeFiles/test_world.dir/world/api_example_test.cpp.o.d"
  "/work/wt/io/tests/world/body_lifecycle_test.cpp" "tests/CMakeFiles/test_world.dir/world/body_lifecycle_test.cpp.o" "gcc" "tests/CMakeFiles/test_world.dir/world/body_lifecycle_test.cpp.o.d"
  "/work/wt/io/tests/world/determinism_and_allocation_test.cpp" "tests/CMakeFiles/test_world.dir/world/determinism_and_allocation_test.cpp.o" "gcc" "tests/CMakeFiles/test_world.dir/world/determinism_and_allocation_test.cpp.o.d"
  "/work/wt/io/tests/world/fixed_stepper_test.cpp" "tests/CMakeFiles/test_world.dir/world/fixed_stepper_test.cpp.o" "gcc" "tests/CMakeFiles/test_world.dir/world/fixed_stepper_test.cpp.o.d"
  "/work/wt/io/tests/world/joints_test.cpp" "tests/CMakeFiles/test_world.dir/world/joints_test.cpp.o" "gcc" "tests/CMakeFiles/test_world.dir/world/joints_test.cpp.o.d"
  "/work/wt/io/tests/world/validation_test.cpp" "tests/CMakeFiles/test_world.dir/world/validation_test.cpp.o" "gcc" "tests/CMakeFiles/test_world.dir/world/validation_test.cpp.o.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  "/work/wt/io/build-asan/CMakeFiles/fulcrum.dir/DependInfo.cmake"
  "/work/wt/io/build-asan/CMakeFiles/fulcrum_io.dir/DependInfo.cmake"
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
