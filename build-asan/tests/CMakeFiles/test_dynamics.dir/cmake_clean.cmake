file(REMOVE_RECURSE
  "CMakeFiles/test_dynamics.dir/dynamics/forces_test.cpp.o"
  "CMakeFiles/test_dynamics.dir/dynamics/forces_test.cpp.o.d"
  "CMakeFiles/test_dynamics.dir/dynamics/free_fall_test.cpp.o"
  "CMakeFiles/test_dynamics.dir/dynamics/free_fall_test.cpp.o.d"
  "CMakeFiles/test_dynamics.dir/dynamics/integrator_figures_test.cpp.o"
  "CMakeFiles/test_dynamics.dir/dynamics/integrator_figures_test.cpp.o.d"
  "CMakeFiles/test_dynamics.dir/dynamics/orbit_test.cpp.o"
  "CMakeFiles/test_dynamics.dir/dynamics/orbit_test.cpp.o.d"
  "CMakeFiles/test_dynamics.dir/dynamics/rigid_rotation_test.cpp.o"
  "CMakeFiles/test_dynamics.dir/dynamics/rigid_rotation_test.cpp.o.d"
  "CMakeFiles/test_dynamics.dir/dynamics/spring_mass_test.cpp.o"
  "CMakeFiles/test_dynamics.dir/dynamics/spring_mass_test.cpp.o.d"
  "test_dynamics"
  "test_dynamics.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_dynamics.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
