
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "/work/wt/io/tests/shapes/hull_test.cpp" "tests/CMakeFiles/test_shapes.dir/shapes/hull_test.cpp.o" "gcc" "tests/CMakeFiles/test_shapes.dir/shapes/hull_test.cpp.o.d"
  "/work/wt/io/tests/shapes/mass_test.cpp" "tests/CMakeFiles/test_shapes.dir/shapes/mass_test.cpp.o" "gcc" "tests/CMakeFiles/test_shapes.dir/shapes/mass_test.cpp.o.d"
  "/work/wt/io/tests/shapes/mesh_test.cpp" "tests/CMakeFiles/test_shapes.dir/shapes/mesh_test.cpp.o" "gcc" "tests/CMakeFiles/test_shapes.dir/shapes/mesh_test.cpp.o.d"
  "/work/wt/io/tests/shapes/queries_test.cpp" "tests/CMakeFiles/test_shapes.dir/shapes/queries_test.cpp.o" "gcc" "tests/CMakeFiles/test_shapes.dir/shapes/queries_test.cpp.o.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  "/work/wt/io/build-asan/CMakeFiles/fulcrum.dir/DependInfo.cmake"
  "/work/wt/io/build-asan/CMakeFiles/fulcrum_io.dir/DependInfo.cmake"
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
