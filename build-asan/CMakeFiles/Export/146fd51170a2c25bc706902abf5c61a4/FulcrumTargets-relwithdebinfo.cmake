#----------------------------------------------------------------
# Generated CMake target import file for configuration "RelWithDebInfo".
#----------------------------------------------------------------

# Commands may need to know the format version.
set(CMAKE_IMPORT_FILE_VERSION 1)

# Import target "fulcrum::fulcrum" for configuration "RelWithDebInfo"
set_property(TARGET fulcrum::fulcrum APPEND PROPERTY IMPORTED_CONFIGURATIONS RELWITHDEBINFO)
set_target_properties(fulcrum::fulcrum PROPERTIES
  IMPORTED_LINK_INTERFACE_LANGUAGES_RELWITHDEBINFO "CXX"
  IMPORTED_LOCATION_RELWITHDEBINFO "${_IMPORT_PREFIX}/lib/libfulcrum.a"
  )

list(APPEND _cmake_import_check_targets fulcrum::fulcrum )
list(APPEND _cmake_import_check_files_for_fulcrum::fulcrum "${_IMPORT_PREFIX}/lib/libfulcrum.a" )

# Import target "fulcrum::fulcrum_io" for configuration "RelWithDebInfo"
set_property(TARGET fulcrum::fulcrum_io APPEND PROPERTY IMPORTED_CONFIGURATIONS RELWITHDEBINFO)
set_target_properties(fulcrum::fulcrum_io PROPERTIES
  IMPORTED_LINK_INTERFACE_LANGUAGES_RELWITHDEBINFO "CXX"
  IMPORTED_LOCATION_RELWITHDEBINFO "${_IMPORT_PREFIX}/lib/libfulcrum_io.a"
  )

list(APPEND _cmake_import_check_targets fulcrum::fulcrum_io )
list(APPEND _cmake_import_check_files_for_fulcrum::fulcrum_io "${_IMPORT_PREFIX}/lib/libfulcrum_io.a" )

# Commands beyond this point should not need to know the version.
set(CMAKE_IMPORT_FILE_VERSION)
