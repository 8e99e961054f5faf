file(REMOVE_RECURSE
  "CMakeFiles/fulcrum_io.dir/src/io/demo.cpp.o"
  "CMakeFiles/fulcrum_io.dir/src/io/demo.cpp.o.d"
  "CMakeFiles/fulcrum_io.dir/src/io/json_locator.cpp.o"
  "CMakeFiles/fulcrum_io.dir/src/io/json_locator.cpp.o.d"
  "CMakeFiles/fulcrum_io.dir/src/io/run.cpp.o"
  "CMakeFiles/fulcrum_io.dir/src/io/run.cpp.o.d"
  "CMakeFiles/fulcrum_io.dir/src/io/scene.cpp.o"
  "CMakeFiles/fulcrum_io.dir/src/io/scene.cpp.o.d"
  "CMakeFiles/fulcrum_io.dir/src/io/scene_detail.cpp.o"
  "CMakeFiles/fulcrum_io.dir/src/io/scene_detail.cpp.o.d"
  "CMakeFiles/fulcrum_io.dir/src/io/scene_parse.cpp.o"
  "CMakeFiles/fulcrum_io.dir/src/io/scene_parse.cpp.o.d"
  "CMakeFiles/fulcrum_io.dir/src/io/scene_world.cpp.o"
  "CMakeFiles/fulcrum_io.dir/src/io/scene_world.cpp.o.d"
  "CMakeFiles/fulcrum_io.dir/src/io/scene_write.cpp.o"
  "CMakeFiles/fulcrum_io.dir/src/io/scene_write.cpp.o.d"
  "CMakeFiles/fulcrum_io.dir/src/io/svg_plot.cpp.o"
  "CMakeFiles/fulcrum_io.dir/src/io/svg_plot.cpp.o.d"
  "libfulcrum_io.a"
  "libfulcrum_io.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/fulcrum_io.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
