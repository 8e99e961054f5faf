file(REMOVE_RECURSE
  "CMakeFiles/fulcrum.dir/src/collision/hull.cpp.o"
  "CMakeFiles/fulcrum.dir/src/collision/hull.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/collision/mesh.cpp.o"
  "CMakeFiles/fulcrum.dir/src/collision/mesh.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/collision/mesh_bvh.cpp.o"
  "CMakeFiles/fulcrum.dir/src/collision/mesh_bvh.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/collision/shape.cpp.o"
  "CMakeFiles/fulcrum.dir/src/collision/shape.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/collision/shape_queries.cpp.o"
  "CMakeFiles/fulcrum.dir/src/collision/shape_queries.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/dynamics/body_mass.cpp.o"
  "CMakeFiles/fulcrum.dir/src/dynamics/body_mass.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/dynamics/forces.cpp.o"
  "CMakeFiles/fulcrum.dir/src/dynamics/forces.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/dynamics/integrators.cpp.o"
  "CMakeFiles/fulcrum.dir/src/dynamics/integrators.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/dynamics/validation.cpp.o"
  "CMakeFiles/fulcrum.dir/src/dynamics/validation.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/world/diagnostics.cpp.o"
  "CMakeFiles/fulcrum.dir/src/world/diagnostics.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/world/names.cpp.o"
  "CMakeFiles/fulcrum.dir/src/world/names.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/world/step.cpp.o"
  "CMakeFiles/fulcrum.dir/src/world/step.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/world/world.cpp.o"
  "CMakeFiles/fulcrum.dir/src/world/world.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/world/world_joints.cpp.o"
  "CMakeFiles/fulcrum.dir/src/world/world_joints.cpp.o.d"
  "CMakeFiles/fulcrum.dir/src/world/world_springs.cpp.o"
  "CMakeFiles/fulcrum.dir/src/world/world_springs.cpp.o.d"
  "libfulcrum.a"
  "libfulcrum.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/fulcrum.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
