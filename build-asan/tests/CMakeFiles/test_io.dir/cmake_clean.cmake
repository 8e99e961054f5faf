file(REMOVE_RECURSE
  "CMakeFiles/test_io.dir/io/scene_parse_test.cpp.o"
  "CMakeFiles/test_io.dir/io/scene_parse_test.cpp.o.d"
  "CMakeFiles/test_io.dir/io/scene_world_test.cpp.o"
  "CMakeFiles/test_io.dir/io/scene_world_test.cpp.o.d"
  "test_io"
  "test_io.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_io.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
