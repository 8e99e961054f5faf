# Debian's CLI11 headers for the WebAssembly build (cmake/wasm/README.md).
include(${CMAKE_CURRENT_LIST_DIR}/../host_headers.cmake)
if(NOT TARGET CLI11::CLI11)
  fulcrum_wasm_host_headers(headers CLI)
  add_library(CLI11::CLI11 INTERFACE IMPORTED)
  set_target_properties(CLI11::CLI11 PROPERTIES INTERFACE_INCLUDE_DIRECTORIES ${headers})
endif()
