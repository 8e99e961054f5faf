#!/usr/bin/env bash
# Builds the engine and the command-line tool for WebAssembly with Debian's
# Emscripten (scripts/install-wasm-deps.sh installs it; no emsdk) into
# build-wasm/: `node build-wasm/fulcrum.js run SCENE.json --json` takes the
# native options and prints the native build's numbers bit for bit (those of
# FULCRUM_SIMD=scalar; docs/determinism.md). Files are read and written
# through Node's own file system (NODERAWFS).
# Usage: scripts/build-wasm.sh [BUILD_DIR]   (default build-wasm)
# WASM_EXTRA_CXX_FLAGS adds compiler flags, for experiments in another
# BUILD_DIR (docs/benchmarks.md: -msimd128).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-wasm-deps.sh
dir=${1:-build-wasm}
here=$(pwd)
# Debian's emcc runs its JavaScript tools with the node on PATH; a node that
# is not Debian's does not look in Debian's module folder for them (acorn).
export NODE_PATH=/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)

# The two libraries the native build takes from Debian, compiled first
# (cmake/wasm/README.md): zlib's compress2 as stored blocks, and tinygltf.
mkdir -p "$dir/wasm-libs/include"
libs=$(cd "$dir/wasm-libs" && pwd)
ln -sfn /usr/include/tiny_gltf.h "$libs/include/tiny_gltf.h"
ln -sfn /usr/include/nlohmann "$libs/include/nlohmann"
if [ ! -f "$libs/libz.a" ]; then
  emcc -O2 -c cmake/wasm/zlib_stored/zlib_stored.c -o "$libs/zlib_stored.o"
  emar rcs "$libs/libz.a" "$libs/zlib_stored.o"
fi
if [ ! -f "$libs/libtinygltf.a" ]; then
  em++ -O2 -std=c++20 -isystem "$libs/include" -c cmake/wasm/TinyGLTF/tinygltf.cpp -o "$libs/tinygltf.o"
  emar rcs "$libs/libtinygltf.a" "$libs/tinygltf.o"
fi

# The engine's own SSE2 kernels (the native build's default path, which has
# the scalar path's bits) on WebAssembly's 128-bit SIMD through Emscripten's
# SSE2 headers: pyramid20 steps 3-4x faster than the scalar path, with the
# same bits (docs/browser.md). LLVM's own loop and SLP vectorizers stay off:
# with them -msimd128 changed the bits of four scenes (docs/benchmarks.md).
# Every browser since 2021-2023 and Node 16.4+ run SIMD128.
simd="-msimd128 -msse2 -fno-vectorize -fno-slp-vectorize"
emcmake cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DFULCRUM_WARNINGS_AS_ERRORS=ON -DFULCRUM_BUILD_TESTS=OFF \
  -DFULCRUM_BUILD_APPS=ON -DFULCRUM_BUILD_PYTHON=OFF "${launcher[@]}" \
  -Dnlohmann_json_DIR="$here/cmake/wasm/nlohmann_json" -DCLI11_DIR="$here/cmake/wasm/CLI11" \
  -DTinyGLTF_DIR="$here/cmake/wasm/TinyGLTF" -DTinyGLTF_LIBRARY="$libs/libtinygltf.a" \
  -DZLIB_INCLUDE_DIR="$here/cmake/wasm/zlib_stored" -DZLIB_LIBRARY="$libs/libz.a" \
  "-DCMAKE_CXX_FLAGS=-include $here/cmake/wasm/libcxx_compat.hpp -fexceptions $simd ${WASM_EXTRA_CXX_FLAGS:-}" -DCMAKE_EXE_LINKER_FLAGS=-fexceptions >/dev/null
# -fexceptions: Emscripten catches no C++ exception by default, so a bad scene
# would end the tool with "exiting due to exception" instead of the engine's
# message, and abort a page using the module; docs/benchmarks.md measures what
# catching costs. Each target's link options are in its CMakeLists.txt
# (apps/fulcrum, apps/web).
cmake --build "$dir" -j "$(nproc)" --target fulcrum_cli fulcrum_web
# The tool as build-wasm/fulcrum.js (+ fulcrum.wasm beside it); the module as
# build-wasm/fulcrum_web.js (one file, the WebAssembly inside).
cp "$dir/apps/fulcrum/fulcrum.js" "$dir/apps/fulcrum/fulcrum.wasm" "$dir/apps/web/fulcrum_web.js" "$dir/"

# The JavaScript API beside the module (docs/browser.md), and the live sandbox
# page (viewer/src/sandbox.html): its bundle (viewer/build-sandbox.mjs, with the
# viewer's node packages: scripts/install-viewer-deps.sh) and the built-in
# scenes (scenes/*.json but those that read URDF, which this build cannot).
cp apps/web/fulcrum_api.js "$dir/fulcrum_api.mjs"
if [ -d viewer/node_modules/esbuild ] && [ -d viewer/node_modules/three ]; then
  (cd viewer && node build-sandbox.mjs "$here/$dir/sandbox.js" >/dev/null)
  cp viewer/src/sandbox.html "$dir/sandbox.html"
  node -e '
    const fs = require("fs"), path = require("path");
    const scenes = {};
    for (const file of process.argv.slice(1).sort()) {
      const text = fs.readFileSync(file, "utf8");
      if (!/"urdf"\s*:/.test(text)) scenes[path.basename(file, ".json")] = text;
    }
    process.stdout.write(`window.FULCRUM_SCENES = ${JSON.stringify(scenes)};\n`);
  ' scenes/*.json > "$dir/sandbox-scenes.js"
  echo "build-wasm: $dir/sandbox.html (the live sandbox)"
else
  rm -f "$dir/sandbox.html"  # never an old page tested as if it were this build's
  echo "build-wasm: no sandbox page (viewer/node_modules missing: scripts/install-viewer-deps.sh)"
fi
echo "build-wasm: $dir/fulcrum.js (node $dir/fulcrum.js run SCENE.json --json), $dir/fulcrum_web.js (docs/browser.md)"
