#!/usr/bin/env bash
# Installs Debian's Emscripten (and what it needs: clang, lld, binaryen,
# Node.js) for scripts/build-wasm.sh, only if missing. Idempotent and quiet.
# Debian's package, not an emsdk download: the same toolchain on every machine.
set -euo pipefail
cd "$(dirname "$0")/.."
exec scripts/install-deps.sh emscripten
