#!/usr/bin/env bash
# Issue 27's speed-up of the 2D path measured inside one process: this checkout's engine and an
# older commit's take turns of 400 steps on their own pull-out beds, each turn's CPU time added
# to its engine (benchmarks/inrun/pull_out_2d_inrun.cpp says why). One core (taskset -c 0).
#   benchmarks/inrun/pull_out_2d_inrun.sh [BUILD_DIR] [BEFORE] [RUNS] [STEPS]
#   (defaults: build-bench, 3e22e0b~1 = commit 395a523, the engine before 2D packing, 3, 20000)
# The bed is benchmarks/pull_out_2d_rounds.sh's for BEFORE (prepared by it if missing). The older engine's
# headers are copied from git into BUILD_DIR/inrun-<hash>/include/granule_before, with the
# namespace granule renamed granule_before (and the GRANULE_ macros GRANULE_BEFORE_), so that
# both engines link into one program; it is built with the flags of the Release benchmarks
# (gnu++20, as CMake gives them: with -std=c++20 GCC does not fuse multiply-adds).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="${1:-$ROOT/build-bench}"
BEFORE="${2:-3e22e0b~1}"
RUNS="${3:-3}"
STEPS="${4:-20000}"
[[ "$RUNS" =~ ^[1-9][0-9]*$ ]] || { echo "RUNS must be a positive integer, got '$RUNS'" >&2; exit 2; }
[[ "$STEPS" =~ ^[1-9][0-9]*$ ]] || { echo "STEPS must be a positive integer, got '$STEPS'" >&2; exit 2; }
hash="$(git -C "$ROOT" rev-parse --short=7 "$BEFORE^{commit}")" ||
  { echo "BEFORE: '$BEFORE' is not a commit of $ROOT" >&2; exit 2; }
"$ROOT/benchmarks/pull_out_2d_rounds.sh" "$BUILD" 0 "$BEFORE"
dir="$BUILD/inrun-$hash"
if [[ ! -d "$dir/include/granule_before" ]]; then
  rm -rf "$dir"
  mkdir -p "$dir"
  git -C "$ROOT" archive "$hash" include/granule | tar -x -C "$dir"
  mv "$dir/include/granule" "$dir/include/granule_before"
  find "$dir/include/granule_before" -type f -exec sed -i -e 's/\bgranule\b/granule_before/g' \
    -e 's/\bGRANULE_/GRANULE_BEFORE_/g' {} +
fi
exe="$dir/bench_pull_out_2d_inrun"
if [[ ! -x "$exe" || "$ROOT/benchmarks/inrun/pull_out_2d_inrun.cpp" -nt "$exe" ||
      -n "$(find "$ROOT/include" "$ROOT/benchmarks/pull_out_2d_scene.hpp" -newer "$exe" -print -quit)" ]]; then
  "${CXX:-g++}" -std=gnu++20 -O3 -DNDEBUG -march=native -fopenmp -I"$ROOT/include" -I"$dir/include" \
    -I/usr/include/eigen3 "$ROOT/benchmarks/inrun/pull_out_2d_inrun.cpp" -o "$exe" -lfftw3
fi
# Both engines start from the older engine's bed (this engine reads older checkpoints; the
# older one cannot read newer ones), so that they start from one state.
bed="$ROOT/out/bench/pull_out_2d_before-$hash.ckpt"
for ((r = 1; r <= RUNS; ++r)); do
  echo "run $r: $(taskset -c 0 "$exe" --now "$bed" --before "$bed" --steps "$STEPS")"
done
