#!/usr/bin/env bash
# The 2D path on paper 002's pull-out bed (1600 disks): the packed pair loop against the scalar
# one, and optionally against the engine of an older commit, in alternating rounds on one core
# (the host's speed swings; docs/performance.md "Machines and method"). The scalar loop is the
# engine's 2D path one contact at a time (its end state was bitwise that of commit 395a523, the
# engine before 2D packing, until the 2D laws became one number along the tangent on
# 2026-12-07); BEFORE=3e22e0b~1 times 395a523 itself, so that ratio is the speed-up of the 2D
# path per core. The three runs follow different trajectories (rounding), and the bed's contact
# count swings with them (0.25-1.46 contacts per disk at the end of the runs): compare rounds.
#   benchmarks/pull_out_2d_rounds.sh [BUILD_DIR] [ROUNDS] [BEFORE]   (defaults: build-bench, 5, none;
#   ROUNDS 0 builds and prepares the beds only)
# Builds bench_scene_pull_out_2d with -march=native if needed, prepares the bed once in
# out/bench/pull_out_2d.ckpt, then prints one line per run and the best of each loop.
# BEFORE (a commit, e.g. 3e22e0b~1, the engine before 2D packing) adds a third column: the same
# benchmark source built against that commit's headers (in BUILD_DIR/before-<hash>, Release,
# GRANULE_NATIVE, as BUILD_DIR). Older engines cannot read this engine's checkpoints, so the
# older engine prepares its own bed from the same seed and procedure
# (out/bench/pull_out_2d_before-<hash>.ckpt) and is timed on it; each line prints the list
# entries and contacts per disk of its bed.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${1:-$ROOT/build-bench}"
ROUNDS="${2:-5}"
BEFORE="${3:-}"
[[ "$ROUNDS" =~ ^[0-9]+$ ]] || { echo "ROUNDS must be a non-negative integer, got '$ROUNDS'" >&2; exit 2; }
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DGRANULE_NATIVE=ON -DGRANULE_BUILD_BENCHMARKS=ON \
  -DGRANULE_BUILD_TESTS=OFF -DGRANULE_BUILD_EXAMPLES=OFF > /dev/null
cmake --build "$BUILD" --target bench_scene_pull_out_2d > /dev/null
EXE="$BUILD/benchmarks/bench_scene_pull_out_2d"
BED="$ROOT/out/bench/pull_out_2d.ckpt"
mkdir -p "$(dirname "$BED")"
[[ -f "$BED" ]] || "$EXE" --prepare "$BED"
loops=(one-at-a-time packed)
if [[ -n "$BEFORE" ]]; then
  hash="$(git -C "$ROOT" rev-parse --short=7 "$BEFORE^{commit}")" ||
    { echo "BEFORE: '$BEFORE' is not a commit of $ROOT" >&2; exit 2; }
  src="$BUILD/before-$hash/src"
  if [[ ! -d "$src" ]]; then
    mkdir -p "$src"
    git -C "$ROOT" archive "$hash" | tar -x -C "$src"
  fi
  # This benchmark's source, as it is now (it compiles against engines back to 395a523).
  cp "$ROOT/benchmarks/scene_pull_out_2d.cpp" "$ROOT/benchmarks/pull_out_2d_scene.hpp" "$src/benchmarks/"
  cmake -S "$src" -B "$BUILD/before-$hash/build" -DCMAKE_BUILD_TYPE=Release -DGRANULE_NATIVE=ON \
    -DGRANULE_BUILD_BENCHMARKS=ON -DGRANULE_BUILD_TESTS=OFF -DGRANULE_BUILD_EXAMPLES=OFF > /dev/null
  cmake --build "$BUILD/before-$hash/build" --target bench_scene_pull_out_2d > /dev/null
  BEFORE_EXE="$BUILD/before-$hash/build/benchmarks/bench_scene_pull_out_2d"
  BEFORE_BED="$ROOT/out/bench/pull_out_2d_before-$hash.ckpt"
  [[ -f "$BEFORE_BED" ]] || "$BEFORE_EXE" --prepare "$BEFORE_BED"
  loops=(before one-at-a-time packed)
fi
# (0 rounds: the builds and beds only, for benchmarks/inrun/pull_out_2d_inrun.sh.)
((ROUNDS > 0)) || exit 0
declare -A best=([before]=1e9 [packed]=1e9 [one-at-a-time]=1e9)
for ((r = 1; r <= ROUNDS; ++r)); do
  for loop in "${loops[@]}"; do
    case $loop in
      before) cmd=("$BEFORE_EXE" --data "$BEFORE_BED") ;;
      one-at-a-time) cmd=("$EXE" --data "$BED" --one-at-a-time) ;;
      packed) cmd=("$EXE" --data "$BED") ;;
    esac
    line="$(taskset -c 0 "${cmd[@]}" --steps 10000 --repeat 3)"
    # (An engine before 3e22e0b has one 2D pair loop, which the line calls packed.)
    [[ $loop == before ]] && line="${line/pair_loop=packed/pair_loop=before-$hash}"
    echo "round $r: $line"
    ns="$(grep -o 'cpu_ns_per_particle_step=[0-9.]*' <<< "$line" | cut -d= -f2)"
    best[$loop]="$(awk -v a="${best[$loop]}" -v b="$ns" 'BEGIN { print (b < a ? b : a) }')"
  done
done
awk -v s="${best[one-at-a-time]}" -v p="${best[packed]}" \
  'BEGIN { printf "best: one-at-a-time %.2f ns, packed %.2f ns per particle-step: %.2fx\n", s, p, s / p }'
if [[ -n "$BEFORE" ]]; then
  awk -v b="${best[before]}" -v s="${best[one-at-a-time]}" -v p="${best[packed]}" -v h="$hash" \
    'BEGIN { printf "best: before (%s) %.2f ns per particle-step: one-at-a-time %.2fx, packed %.2fx faster\n", h, b, b / s, b / p }'
fi
