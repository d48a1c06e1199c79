#!/usr/bin/env bash
# The OpenMP wait policy on a 2-core machine (docs/performance.md, "Threads on a shared machine"):
# examples/02_pour_settle (2000 beads poured and settled) alone, and two copies at once (a machine
# that another job keeps busy), with 1 and 2 threads, with the runtime's default policy and with
# OMP_WAIT_POLICY=passive. Prints one line per run with the wall times.
#   benchmarks/wait_policy.sh [repetitions]      (default 3; builds build/ first)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$ROOT/granule.sh" build -- --target 02_pour_settle >/dev/null
EXE="$ROOT/build/examples/02_pour_settle"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT

# one POLICY THREADS TAG: one run; its wall time goes to $WORK/t.TAG
one() {
  local env_args=(env -u OMP_WAIT_POLICY)
  [[ $1 == default ]] || env_args+=("OMP_WAIT_POLICY=$1")
  "${env_args[@]}" /usr/bin/time -f "%e" -o "$WORK/t.$3" \
    "$EXE" --particles 2000 --vtk-every 0 --threads "$2" --out "$WORK/o.$3" >/dev/null 2>&1
}

echo "policy,threads,repetition,alone [s],two at once: first [s],two at once: second [s]"
for rep in $(seq 1 "${1:-3}"); do
  for policy in default passive; do
    for threads in 1 2; do
      one "$policy" "$threads" a
      alone="$(cat "$WORK/t.a")"
      one "$policy" "$threads" a &
      one "$policy" "$threads" b &
      wait
      echo "$policy,$threads,$rep,$alone,$(cat "$WORK/t.a"),$(cat "$WORK/t.b")"
    done
  done
done
