
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "/work/wt/io/src/io/demo.cpp" "CMakeFiles/fulcrum_io.dir/src/io/demo.cpp.o" "gcc" "CMakeFiles/fulcrum_io.dir/src/io/demo.cpp.o.d"
  "/work/wt/io/src/io/json_locator.cpp" "CMakeFiles/fulcrum_io.dir/src/io/json_locator.cpp.o" "gcc" "CMakeFiles/fulcrum_io.dir/src/io/json_locator.cpp.o.d"
  "/work/wt/io/src/io/run.cpp" "CMakeFiles/fulcrum_io.dir/src/io/run.cpp.o" "gcc" "CMakeFiles/fulcrum_io.dir/src/io/run.cpp.o.d"
  "/work/wt/io/src/io/scene.cpp" "CMakeFiles/fulcrum_io.dir/src/io/scene.cpp.o" "gcc" "CMakeFiles/fulcrum_io.dir/src/io/scene.cpp.o.d"
  "/work/wt/io/src/io/scene_detail.cpp" "CMakeFiles/fulcrum_io.dir/src/io/scene_detail.cpp.o" "gcc" "CMakeFiles/fulcrum_io.dir/src/io/scene_detail.cpp.o.d"
  "/work/wt/io/src/io/scene_parse.cpp" "CMakeFiles/fulcrum_io.dir/src/io/scene_parse.cpp.o" "gcc" "CMakeFiles/fulcrum_io.dir/src/io/scene_parse.cpp.o.d"
  "/work/wt/io/src/io/scene_world.cpp" "CMakeFiles/fulcrum_io.dir/src/io/scene_world.cpp.o" "gcc" "CMakeFiles/fulcrum_io.dir/src/io/scene_world.cpp.o.d"
  "/work/wt/io/src/io/scene_write.cpp" "CMakeFiles/fulcrum_io.dir/src/io/scene_write.cpp.o" "gcc" "CMakeFiles/fulcrum_io.dir/src/io/scene_write.cpp.o.d"
  "/work/wt/io/src/io/svg_plot.cpp" "CMakeFiles/fulcrum_io.dir/src/io/svg_plot.cpp.o" "gcc" "CMakeFiles/fulcrum_io.dir/src/io/svg_plot.cpp.o.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  "/work/wt/io/build-asan/CMakeFiles/fulcrum.dir/DependInfo.cmake"
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
