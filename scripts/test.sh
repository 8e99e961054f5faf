#!/usr/bin/env bash
# Builds and runs every test: the WebAssembly build (scripts/build-wasm.sh),
# a Release build (GCC) with warnings as errors,
# then an AddressSanitizer + UndefinedBehaviorSanitizer build with Clang, so
# the suite also runs under the second compiler: GoldenHash.* in both passes
# holds each to the same recorded state bits (docs/determinism.md); then the
# double-precision build (docs/double-precision.md); then a bounded run of
# every fuzz target (scripts/fuzz.sh).
# Usage: scripts/test.sh [--quick]   (--quick: the Release pass only)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
# Headless Chromium and the viewer's node packages, for the replay page's
# browser test; if they can't be installed the test reports SKIPPED, never passes.
scripts/install-viewer-deps.sh || echo "test.sh: viewer dependencies unavailable; the browser test will be skipped"
jobs=$(nproc)
quick=0
[ "${1:-}" = "--quick" ] && quick=1

run_suite() {  # name, build dir, ctest args (one word), extra cmake args...
  local name=$1 dir=$2 ctest_args=$3; shift 3
  echo "== $name build"
  scripts/configure.sh "$dir" "$@"
  cmake --build "$dir" -j "$jobs"
  echo "== $name tests"
  ctest --test-dir "$dir" -j "$jobs" --output-on-failure --timeout 300 $ctest_args
}

# WebAssembly (docs/browser.md): the command-line tool and the JavaScript
# module built with Debian's Emscripten (ccache as its compiler launcher)
# before the Release pass, whose tests then hold them to the native bits:
# Wasm.CliMatchesNative (node build-wasm/fulcrum.js against the native tool,
# FULCRUM_SIMD=scalar, every number: pyramid20, the chain, the cloth, joints,
# every shape) and Browser.SandboxLive (the live page in Chromium, its state
# hash against the native build's). If Emscripten cannot be installed, the
# old build is removed so that those tests report SKIPPED, never pass; a build
# that fails fails the run. Cost on the 2-core machine: about 9 min cold
# (3.3 min of CPU; the rest was waiting on other builds), 1 min 50 s for a new
# build-wasm/ with ccache warm, 5 s when nothing changed; the three tests add
# about 45 s.
echo "== WebAssembly build"
if scripts/install-wasm-deps.sh; then
  scripts/build-wasm.sh build-wasm
else
  rm -f build-wasm/fulcrum.js build-wasm/fulcrum_web.js build-wasm/sandbox.html
  echo "test.sh: Emscripten unavailable; the WebAssembly tests will be SKIPPED"
fi
run_suite "Release" build/release "" -DCMAKE_BUILD_TYPE=Release -DFULCRUM_BUILD_PYTHON=ON
# The Python package (docs/python.md), with Debian's interpreter (the python3 on
# PATH may lack NumPy); the Release pass only (an ASan extension needs LD_PRELOAD).
echo "== Python tests"
FULCRUM_CLI=build/release/apps/fulcrum/fulcrum PYTHONPATH=build/release/python /usr/bin/python3 -m pytest -p no:cacheprovider python/tests -q
if [ $quick -eq 0 ]; then
  # The sanitizer pass: -O1 with line tables only (half the build time of -O2 -g,
  # same reports with file:line), and assertions left on (no NDEBUG). The
  # browser test runs in the Release pass only: its C++ part (writing the page)
  # is covered by the other recording tests, and Chromium isn't instrumented.
  # FULCRUM_VALIDATE: every step of every test also checks the engine's
  # internal invariants at each phase (docs/validation.md).
  # Clang (Debian's), in its own build folder (a folder's compiler is fixed
  # when it is first configured).
  sanitize_ctest_args="-E ^(Browser|Wasm)\."
  CC=clang CXX=clang++ ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    run_suite "ASan+UBSan (Clang)" build/sanitize-clang "$sanitize_ctest_args" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFULCRUM_SANITIZE=ON \
      -DFULCRUM_VALIDATE=ON "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1"
fi
if [ $quick -eq 0 ]; then
  # The double-precision build (-DFULCRUM_DOUBLE=ON, docs/double-precision.md):
  # Real = double everywhere, its own golden hashes
  # (tests/determinism/golden_hashes_double.txt) and the large-world test at
  # 10^6 m (tests/world/large_world_test.cpp). GCC Release in its own folder,
  # without Python (the binding is the same source over Real) and without the
  # browser and WebAssembly tests (the replay page is float32 in both builds;
  # the WebAssembly build is float and compared with the float native build).
  run_suite "Double precision" build/double "-E ^(Browser|Wasm)\." -DCMAKE_BUILD_TYPE=Release -DFULCRUM_DOUBLE=ON
fi
if [ $quick -eq 0 ]; then
  # Fuzzing (docs/reliability.md, "Fuzzing"): every libFuzzer target of fuzz/
  # for FUZZ_SECONDS (default 40) from its corpus, so that a change that
  # crashes a loader cannot land. Its own build (build/fuzz: clang, the engine
  # and the targets only). A finding fails the run and names the input.
  # A fixed seed (FUZZ_SEED, default 1) and a fixed number of inputs
  # (FUZZ_RUNS, default 150,000, with FUZZ_SECONDS as a cap): every run of the
  # test command mutates the same way from the same corpus and tries the same
  # inputs, however fast the machine (a time bound alone let a faster machine
  # reach inputs a slower one never tried), so a finding here comes back on a
  # second run; exploring is for the long runs by hand (scripts/fuzz.sh).
  echo "== Fuzz build"
  scripts/fuzz.sh --build
  mkdir -p build/fuzz/logs
  for target in $(scripts/fuzz.sh --list); do
    log=build/fuzz/logs/$target.log
    if scripts/fuzz.sh "$target" "${FUZZ_SECONDS:-40}" -seed="${FUZZ_SEED:-1}" -runs="${FUZZ_RUNS:-150000}" >"$log" 2>&1; then
      echo "== Fuzz $target: $(sed -n 's/^stat::number_of_executed_units: //p' "$log") inputs, no finding"
    else
      tail -n 60 "$log"
      echo "test.sh: the fuzz target $target found a problem (log: $log; the input: build/fuzz/artifacts/$target/;" \
           "reproduce: build/fuzz/fuzz/fuzz_$target FILE)"
      exit 1
    fi
  done
fi
