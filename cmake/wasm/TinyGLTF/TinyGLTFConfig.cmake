# tinygltf for the WebAssembly build (cmake/wasm/README.md): Debian's header,
# and its implementation compiled by scripts/build-wasm.sh into
# TinyGLTF_LIBRARY (tinygltf.cpp here) before CMake runs, so that it is an
# imported library like the native package's.
include(${CMAKE_CURRENT_LIST_DIR}/../host_headers.cmake)
if(NOT TARGET TinyGLTF::TinyGLTF)
  fulcrum_wasm_host_headers(headers tiny_gltf.h nlohmann)
  add_library(TinyGLTF::TinyGLTF STATIC IMPORTED)
  set_target_properties(TinyGLTF::TinyGLTF PROPERTIES IMPORTED_LOCATION ${TinyGLTF_LIBRARY}
                        INTERFACE_INCLUDE_DIRECTORIES ${headers}
                        # Its users see the header as tinygltf.cpp compiled it (no image codecs).
                        INTERFACE_COMPILE_DEFINITIONS "TINYGLTF_NO_STB_IMAGE;TINYGLTF_NO_STB_IMAGE_WRITE;TINYGLTF_NO_EXTERNAL_IMAGE")
endif()
