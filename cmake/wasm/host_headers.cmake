# A folder holding only the named host header files and folders (symbolic
# links), so that the Emscripten build sees them and nothing else of /usr/include.
function(fulcrum_wasm_host_headers out)
  set(dir ${CMAKE_BINARY_DIR}/wasm-host-headers)
  file(MAKE_DIRECTORY ${dir})
  foreach(name ${ARGN})
    if(NOT EXISTS ${dir}/${name})
      file(CREATE_LINK /usr/include/${name} ${dir}/${name} SYMBOLIC)
    endif()
  endforeach()
  set(${out} ${dir} PARENT_SCOPE)
endfunction()
