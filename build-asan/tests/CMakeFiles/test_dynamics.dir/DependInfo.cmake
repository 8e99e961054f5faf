
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "/work/wt/io/tests/dynamics/forces_test.cpp" "tests/CMakeFiles/test_dynamics.dir/dynamics/forces_test.cpp.o" "gcc" "tests/CMakeFiles/test_dynamics.dir/dynamics/forces_test.cpp.o.d"
  "/work/wt/io/tests/dynamics/free_fall_test.cpp" "tests/CMakeFiles/test_dynamics.dir/dynamics/free_fall_test.cpp.o" "gcc" "tests/CMakeFiles/test_dynamics.dir/dynamics/free_fall_test.cpp.o.d"
  "/work/wt/io/tests/dynamics/integrator_figures_test.cpp" "tests/CMakeFiles/test_dynamics.dir/dynamics/integrator_figures_test.cpp.o" "gcc" "tests/CMakeFiles/test_dynamics.dir/dynamics/integrator_figures_test.cpp.o.d"
  "/work/wt/io/tests/dynamics/orbit_test.cpp" "tests/CMakeFiles/test_dynamics.dir/dynamics/orbit_test.cpp.o" "gcc" "tests/CMakeFiles/test_dynamics.dir/dynamics/orbit_test.cpp.o.d"
  "/work/wt/io/tests/dynamics/rigid_rotation_test.cpp" "tests/CMakeFiles/test_dynamics.dir/dynamics/rigid_rotation_test.cpp.o" "gcc" "tests/CMakeFiles/test_dynamics.dir/dynamics/rigid_rotation_test.cpp.o.d"
  "/work/wt/io/tests/dynamics/spring_mass_test.cpp" "tests/CMakeFiles/test_dynamics.dir/dynamics/spring_mass_test.cpp.o" "gcc" "tests/CMakeFiles/test_dynamics.dir/dynamics/spring_mass_test.cpp.o.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  "/work/wt/io/build-asan/CMakeFiles/fulcrum.dir/DependInfo.cmake"
  "/work/wt/io/build-asan/CMakeFiles/fulcrum_io.dir/DependInfo.cmake"
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
