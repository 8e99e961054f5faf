#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, Debian's clang) and runs one of them.
#   scripts/fuzz.sh TARGET SECONDS   run TARGET for SECONDS from fuzz/corpus/TARGET
#   scripts/fuzz.sh --list           the targets, one a line
#   scripts/fuzz.sh --build          build them all and stop
# Exits non-zero on a crash, a leak, a timeout (an input running over
# FUZZ_TIMEOUT seconds, default 20), running out of memory (FUZZ_RSS_MB,
# default 2048) or any sanitizer report; the input that did it is written to
# build/fuzz/artifacts/TARGET/ and named in the output. New inputs the run
# finds go to build/fuzz/corpus/TARGET/, never into the repository's corpus
# (merge the useful ones by hand: docs/reliability.md, "Fuzzing").
# More libFuzzer flags may follow SECONDS (e.g. -jobs=2, -seed=1).
# FUZZ_BUILD_DIR builds elsewhere (e.g. a cold build to time it).
set -euo pipefail
cd "$(dirname "$0")/.."

targets() { sed -n 's/^fulcrum_fuzz_target(\([a-z_0-9]*\).*/\1/p' fuzz/CMakeLists.txt; }

build_dir=${FUZZ_BUILD_DIR:-build/fuzz}
build() {
  local cc=clang cxx=clang++ launcher=()
  command -v "$cxx" >/dev/null || { echo "fuzz.sh: clang++ not found: run scripts/install-deps.sh" >&2; exit 2; }
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  # Only the engine, fulcrum::io and the targets: no tests, tools or Python.
  # -O1 with line tables, as the sanitizer pass of scripts/test.sh: half the
  # build time of -O2, and the reports name file:line.
  if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    CC=$cc CXX=$cxx cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" \
      -DFULCRUM_FUZZ=ON -DFULCRUM_BUILD_TESTS=OFF -DFULCRUM_BUILD_APPS=OFF -DFULCRUM_BUILD_PYTHON=OFF "${launcher[@]}" >/dev/null
  fi
  local names=()
  for t in $(targets); do names+=("fuzz_$t"); done
  cmake --build "$build_dir" -j "${FUZZ_JOBS:-$(nproc)}" --target "${names[@]}"
}

case "${1:-}" in
  --list) targets; exit 0 ;;
  --build) build; exit 0 ;;
  ""|-h|--help) sed -n '2,/^set /p' "$0" | sed -n 's/^# \{0,1\}//p'; exit 2 ;;
esac
target=$1
seconds=${2:?"usage: scripts/fuzz.sh TARGET SECONDS (scripts/fuzz.sh --list names the targets)"}
shift 2
targets | grep -qx "$target" || { echo "fuzz.sh: no target '$target' (scripts/fuzz.sh --list)" >&2; exit 2; }
build
mkdir -p "$build_dir/corpus/$target" "$build_dir/artifacts/$target"
seeds=()
[ -d "fuzz/corpus/$target" ] && seeds=("fuzz/corpus/$target")
# detect_leaks: a leak is a finding too; halt_on_error and
# -fno-sanitize-recover make every UBSan report fatal.
ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0} \
UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} \
  "$build_dir/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout="${FUZZ_TIMEOUT:-20}" \
    -rss_limit_mb="${FUZZ_RSS_MB:-2048}" -print_final_stats=1 \
    -artifact_prefix="$build_dir/artifacts/$target/" "$@" \
    "$build_dir/corpus/$target" "${seeds[@]}"
