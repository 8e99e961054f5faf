file(REMOVE_RECURSE
  "CMakeFiles/test_shapes.dir/shapes/hull_test.cpp.o"
  "CMakeFiles/test_shapes.dir/shapes/hull_test.cpp.o.d"
  "CMakeFiles/test_shapes.dir/shapes/mass_test.cpp.o"
  "CMakeFiles/test_shapes.dir/shapes/mass_test.cpp.o.d"
  "CMakeFiles/test_shapes.dir/shapes/mesh_test.cpp.o"
  "CMakeFiles/test_shapes.dir/shapes/mesh_test.cpp.o.d"
  "CMakeFiles/test_shapes.dir/shapes/queries_test.cpp.o"
  "CMakeFiles/test_shapes.dir/shapes/queries_test.cpp.o.d"
  "test_shapes"
  "test_shapes.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_shapes.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
