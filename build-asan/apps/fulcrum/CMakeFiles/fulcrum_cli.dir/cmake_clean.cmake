file(REMOVE_RECURSE
  "CMakeFiles/fulcrum_cli.dir/main.cpp.o"
  "CMakeFiles/fulcrum_cli.dir/main.cpp.o.d"
  "fulcrum"
  "fulcrum.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/fulcrum_cli.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
