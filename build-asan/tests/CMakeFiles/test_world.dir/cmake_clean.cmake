file(REMOVE_RECURSE
  "CMakeFiles/test_world.dir/world/api_example_test.cpp.o"
  "CMakeFiles/test_world.dir/world/api_example_test.cpp.o.d"
  "CMakeFiles/test_world.dir/world/body_lifecycle_test.cpp.o"
  "CMakeFiles/test_world.dir/world/body_lifecycle_test.cpp.o.d"
  "CMakeFiles/test_world.dir/world/determinism_and_allocation_test.cpp.o"
  "CMakeFiles/test_world.dir/world/determinism_and_allocation_test.cpp.o.d"
  "CMakeFiles/test_world.dir/world/fixed_stepper_test.cpp.o"
  "CMakeFiles/test_world.dir/world/fixed_stepper_test.cpp.o.d"
  "CMakeFiles/test_world.dir/world/joints_test.cpp.o"
  "CMakeFiles/test_world.dir/world/joints_test.cpp.o.d"
  "CMakeFiles/test_world.dir/world/validation_test.cpp.o"
  "CMakeFiles/test_world.dir/world/validation_test.cpp.o.d"
  "test_world"
  "test_world.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_world.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
