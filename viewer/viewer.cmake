# Embeds the replay viewer into fulcrum_io (included from the root CMakeLists.txt).
#
# By default the committed bundle viewer/dist/viewer.js is embedded, so a C++
# build needs neither node nor npm. With -DFULCRUM_BUILD_VIEWER=ON the bundle is
# rebuilt from viewer/src with esbuild (node and viewer/node_modules required:
# scripts/install-viewer-deps.sh) into the build tree and that one is embedded.
option(FULCRUM_BUILD_VIEWER "Rebuild the replay viewer bundle with npm/esbuild instead of embedding viewer/dist/viewer.js" OFF)

function(fulcrum_embed_viewer target)
  set(viewer_dir ${PROJECT_SOURCE_DIR}/viewer)
  set(script ${viewer_dir}/dist/viewer.js)
  if(FULCRUM_BUILD_VIEWER)
    find_program(FULCRUM_NODE node)
    if(NOT FULCRUM_NODE OR NOT EXISTS ${viewer_dir}/node_modules/esbuild)
      message(FATAL_ERROR "FULCRUM_BUILD_VIEWER needs node and viewer/node_modules: run scripts/install-viewer-deps.sh")
    endif()
    set(script ${CMAKE_CURRENT_BINARY_DIR}/viewer/viewer.js)
    file(GLOB viewer_sources CONFIGURE_DEPENDS ${viewer_dir}/src/*.js)
    add_custom_command(OUTPUT ${script}
      COMMAND ${FULCRUM_NODE} build.mjs ${script}
      WORKING_DIRECTORY ${viewer_dir}
      DEPENDS ${viewer_sources} ${viewer_dir}/build.mjs ${viewer_dir}/package.json
      COMMENT "Bundling the replay viewer with esbuild"
      VERBATIM)
  endif()
  set(generated ${CMAKE_CURRENT_BINARY_DIR}/generated/viewer_assets.cpp)
  add_custom_command(OUTPUT ${generated}
    COMMAND ${CMAKE_COMMAND} -DSCRIPT=${script} -DTEMPLATE=${viewer_dir}/src/template.html -DOUT=${generated}
            -P ${viewer_dir}/embed_assets.cmake
    DEPENDS ${script} ${viewer_dir}/src/template.html ${viewer_dir}/embed_assets.cmake
    COMMENT "Embedding the replay viewer"
    VERBATIM)
  target_sources(${target} PRIVATE ${generated})
endfunction()
