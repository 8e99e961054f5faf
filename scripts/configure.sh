#!/usr/bin/env bash
# Configures a build folder with the options the scripts share, so that
# scripts/run.sh and the Release pass of scripts/test.sh configure build/release
# the same way: neither recompiles what the other has built.
# Usage: scripts/configure.sh BUILD_DIR [more cmake arguments...]
set -euo pipefail
cd "$(dirname "$0")/.."
dir=$1
shift
cmake -S . -B "$dir" -DFULCRUM_WARNINGS_AS_ERRORS=ON -DFULCRUM_BUILD_TESTS=ON -DFULCRUM_BUILD_APPS=ON "$@" >/dev/null
