
# Consider dependencies only in project.
set(CMAKE_DEPENDS_IN_PROJECT_ONLY OFF)

# The set of languages for which implicit dependencies are needed:
set(CMAKE_DEPENDS_LANGUAGES
  )

# The set of dependency files which are needed:
set(CMAKE_DEPENDS_DEPENDENCY_FILES
  "/work/wt/io/src/collision/hull.cpp" "CMakeFiles/fulcrum.dir/src/collision/hull.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/collision/hull.cpp.o.d"
  "/work/wt/io/src/collision/mesh.cpp" "CMakeFiles/fulcrum.dir/src/collision/mesh.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/collision/mesh.cpp.o.d"
  "/work/wt/io/src/collision/mesh_bvh.cpp" "CMakeFiles/fulcrum.dir/src/collision/mesh_bvh.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/collision/mesh_bvh.cpp.o.d"
  "/work/wt/io/src/collision/shape.cpp" "CMakeFiles/fulcrum.dir/src/collision/shape.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/collision/shape.cpp.o.d"
  "/work/wt/io/src/collision/shape_queries.cpp" "CMakeFiles/fulcrum.dir/src/collision/shape_queries.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/collision/shape_queries.cpp.o.d"
  "/work/wt/io/src/dynamics/body_mass.cpp" "CMakeFiles/fulcrum.dir/src/dynamics/body_mass.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/dynamics/body_mass.cpp.o.d"
  "/work/wt/io/src/dynamics/forces.cpp" "CMakeFiles/fulcrum.dir/src/dynamics/forces.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/dynamics/forces.cpp.o.d"
  "/work/wt/io/src/dynamics/integrators.cpp" "CMakeFiles/fulcrum.dir/src/dynamics/integrators.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/dynamics/integrators.cpp.o.d"
  "/work/wt/io/src/dynamics/validation.cpp" "CMakeFiles/fulcrum.dir/src/dynamics/validation.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/dynamics/validation.cpp.o.d"
  "/work/wt/io/src/world/diagnostics.cpp" "CMakeFiles/fulcrum.dir/src/world/diagnostics.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/world/diagnostics.cpp.o.d"
  "/work/wt/io/src/world/names.cpp" "CMakeFiles/fulcrum.dir/src/world/names.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/world/names.cpp.o.d"
  "/work/wt/io/src/world/step.cpp" "CMakeFiles/fulcrum.dir/src/world/step.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/world/step.cpp.o.d"
  "/work/wt/io/src/world/world.cpp" "CMakeFiles/fulcrum.dir/src/world/world.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/world/world.cpp.o.d"
  "/work/wt/io/src/world/world_joints.cpp" "CMakeFiles/fulcrum.dir/src/world/world_joints.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/world/world_joints.cpp.o.d"
  "/work/wt/io/src/world/world_springs.cpp" "CMakeFiles/fulcrum.dir/src/world/world_springs.cpp.o" "gcc" "CMakeFiles/fulcrum.dir/src/world/world_springs.cpp.o.d"
  )

# Targets to which this target links.
set(CMAKE_TARGET_LINKED_INFO_FILES
  )

# Fortran module output directory.
set(CMAKE_Fortran_TARGET_MODULE_DIR "")
