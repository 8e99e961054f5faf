# Debian's nlohmann-json header for the WebAssembly build (cmake/wasm/README.md).
include(${CMAKE_CURRENT_LIST_DIR}/../host_headers.cmake)
if(NOT TARGET nlohmann_json::nlohmann_json)
  fulcrum_wasm_host_headers(headers nlohmann)
  add_library(nlohmann_json::nlohmann_json INTERFACE IMPORTED)
  set_target_properties(nlohmann_json::nlohmann_json PROPERTIES INTERFACE_INCLUDE_DIRECTORIES ${headers})
endif()
