#!/usr/bin/env bash
# Installs what the replay viewer needs beyond scripts/install-deps.sh, and only
# what is missing: Debian's chromium (for the headless browser test) and the
# node packages of viewer/package.json (three.js and esbuild to rebuild the
# bundle, playwright-core to drive Chromium, gltf-validator for the Khronos
# glTF check). Idempotent.
# Usage: scripts/install-viewer-deps.sh [--no-browser]
set -euo pipefail
cd "$(dirname "$0")/.."

if [ "${1:-}" != "--no-browser" ] && ! command -v chromium >/dev/null 2>&1; then
  echo "install-viewer-deps: installing chromium"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends chromium >/dev/null
fi

if ! command -v npm >/dev/null 2>&1; then
  echo "install-viewer-deps: installing nodejs and npm"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
fi
if [ ! -d viewer/node_modules/three ] || [ ! -d viewer/node_modules/esbuild ] || [ ! -d viewer/node_modules/playwright-core ] || [ ! -d viewer/node_modules/gltf-validator ]; then
  echo "install-viewer-deps: npm install in viewer/"
  (cd viewer && npm install --no-audit --no-fund --loglevel=error)
fi
