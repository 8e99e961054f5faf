
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "/work/wt/io/apps/fulcrum/main.cpp" "apps/fulcrum/CMakeFiles/fulcrum_cli.dir/main.cpp.o" "gcc" "apps/fulcrum/CMakeFiles/fulcrum_cli.dir/main.cpp.o.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  "/work/wt/io/build-asan/CMakeFiles/fulcrum.dir/DependInfo.cmake"
  "/work/wt/io/build-asan/CMakeFiles/fulcrum_io.dir/DependInfo.cmake"
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
