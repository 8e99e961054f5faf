#!/usr/bin/env bash
# Builds Fulcrum (Release) and runs the main job.
#   scripts/run.sh                      the built-in showcase demo, recorded as a
#                                       replay page: build/demo.html
#   scripts/run.sh SCENE.json [options] `fulcrum run` with exactly these arguments
#   scripts/run.sh --OPTION ...         the demo with these options, passed through unchanged
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
# The same folder and options as the Release pass of scripts/test.sh
# (scripts/configure.sh), so the tests reuse everything built here.
scripts/configure.sh build/release -DCMAKE_BUILD_TYPE=Release
cmake --build build/release --target fulcrum_cli -j "$(nproc)"
fulcrum=build/release/apps/fulcrum/fulcrum
if [ "$#" -eq 0 ]; then
    "$fulcrum" run --record build/demo.html
    echo "replay page written to build/demo.html — open it in a browser"
    exit 0
fi
exec "$fulcrum" run "$@"
