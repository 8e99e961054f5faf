file(REMOVE_RECURSE
  "CMakeFiles/test_math.dir/math/math_test.cpp.o"
  "CMakeFiles/test_math.dir/math/math_test.cpp.o.d"
  "test_math"
  "test_math.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang CXX)
  include(CMakeFiles/test_math.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
