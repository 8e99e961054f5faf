#!/usr/bin/env bash
# Builds Fulcrum (Release) and runs the main job: `fulcrum run` on the built-in
# demo, or on the scene and options given. Usage: scripts/run.sh [SCENE.json] [options]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DFULCRUM_BUILD_TESTS=OFF >/dev/null
cmake --build build/release --target fulcrum_cli -j "$(nproc)"
exec build/release/apps/fulcrum/fulcrum run "$@"
