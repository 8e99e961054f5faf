#!/usr/bin/env bash
# Builds Release with benchmarks and runs the scene benchmark (Fulcrum and
# Bullet side by side, docs/benchmarks.md). Usage: scripts/bench.sh [--quick] [--scene NAME]
set -euo pipefail
cd "$(dirname "$0")/.."

# Set-up: Bullet 3 from Debian's packages (optional; without it Fulcrum runs alone).
if ! pkg-config --exists bullet 2>/dev/null && [ ! -f /usr/include/bullet/btBulletDynamicsCommon.h ]; then
    if command -v apt-get >/dev/null 2>&1; then
        echo "bench.sh: installing libbullet-dev" >&2
        SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
        $SUDO apt-get install -y libbullet-dev || echo "bench.sh: could not install Bullet; running Fulcrum alone" >&2
    fi
fi

BUILD=${BUILD_DIR:-build-bench}
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DFULCRUM_BUILD_BENCH=ON >/dev/null
cmake --build "$BUILD" -j2 --target bench_benchmark_scenes
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
"$BUILD"/bench/bench_benchmark_scenes "$@"
