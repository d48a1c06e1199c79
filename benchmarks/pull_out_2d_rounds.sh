#!/usr/bin/env bash
# The 2D path on paper 002's pull-out bed (1600 disks): the packed pair loop against the scalar
# one, in alternating rounds on one core (the host's speed swings; docs/performance.md "Machines
# and method"). The scalar loop is the engine's 2D path before packing (its end state is bitwise
# that of commit 395a523), so the ratio is the speed-up of the 2D path per core.
#   benchmarks/pull_out_2d_rounds.sh [BUILD_DIR] [ROUNDS]     (defaults: build-bench, 5)
# Builds bench_scene_pull_out_2d with -march=native if needed, prepares the bed once in
# out/bench/pull_out_2d.ckpt, then prints one line per run and the best of each loop.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${1:-$ROOT/build-bench}"
ROUNDS="${2:-5}"
[[ "$ROUNDS" =~ ^[1-9][0-9]*$ ]] || { echo "ROUNDS must be a positive integer, got '$ROUNDS'" >&2; exit 2; }
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DGRANULE_NATIVE=ON -DGRANULE_BUILD_BENCHMARKS=ON \
  -DGRANULE_BUILD_TESTS=OFF -DGRANULE_BUILD_EXAMPLES=OFF > /dev/null
cmake --build "$BUILD" --target bench_scene_pull_out_2d > /dev/null
EXE="$BUILD/benchmarks/bench_scene_pull_out_2d"
BED="$ROOT/out/bench/pull_out_2d.ckpt"
mkdir -p "$(dirname "$BED")"
[[ -f "$BED" ]] || "$EXE" --prepare "$BED"
declare -A best=([packed]=1e9 [one-at-a-time]=1e9)
for ((r = 1; r <= ROUNDS; ++r)); do
  for loop in one-at-a-time packed; do
    flag=()
    [[ $loop == one-at-a-time ]] && flag=(--one-at-a-time)
    line="$(taskset -c 0 "$EXE" --data "$BED" --steps 10000 --repeat 3 "${flag[@]}")"
    echo "round $r: $line"
    ns="$(grep -o 'cpu_ns_per_particle_step=[0-9.]*' <<< "$line" | cut -d= -f2)"
    best[$loop]="$(awk -v a="${best[$loop]}" -v b="$ns" 'BEGIN { print (b < a ? b : a) }')"
  done
done
awk -v s="${best[one-at-a-time]}" -v p="${best[packed]}" \
  'BEGIN { printf "best: one-at-a-time %.2f ns, packed %.2f ns per particle-step: %.2fx\n", s, p, s / p }'
