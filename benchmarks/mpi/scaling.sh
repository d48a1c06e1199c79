#!/usr/bin/env bash
# The scaling measurements of docs/performance.md ("Distributed runs"), on the 100k beds A and B
# of bench_scene_throughput (benchmarks/beds.hpp): for each scene,
#   one process (SingleProcess policy) x 1 thread, and x 2 threads,
#   MPI 1 rank x 1 thread, 1 rank x 2 threads, 2 ranks x 1 thread (strong scaling, hybrid against
#   pure MPI), MPI 1 rank x 1 thread on the 50k bed (weak scaling: 50k per rank),
#   2 ranks x 1 thread with a small skin (the resting bed's creep rebuilds the list every few
#   steps) and a rebalance at every rebuild (threshold 1.0): the per-rebuild costs.
#   benchmarks/mpi/scaling.sh [BUILD_DIR] [STEPS] [REPEAT] [ROUNDS]   (defaults: build-mpi, 500, 2, 2)
# The whole set runs ROUNDS times in turn (the host's speed swings; best of the rounds is shown).
# Ranks of one thread are bound to a core (unbound, two ranks polling for messages can share a
# core for a while: the ghost refresh then waits ms instead of ~0.1 ms); a rank of two threads
# is not bound.
# Needs GRANULE_MPI=ON in BUILD_DIR and Open MPI (./granule.sh test-mpi installs it). Prepares
# the beds once in out/bench/ (a few minutes each, 2 threads). Every run's summary line goes to
# benchmarks/mpi/results/scaling.csv (with commit, date and machine; docs/performance.md cites it); a table is printed at the end.
# Run it on a quiet machine: a second job on a 2-core machine halves whichever run it meets.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="${1:-$ROOT/build-mpi}"
STEPS="${2:-500}"
REPEAT="${3:-2}"
ROUNDS="${4:-2}"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DGRANULE_MPI=ON -DGRANULE_BUILD_BENCHMARKS=ON > /dev/null
cmake --build "$BUILD" --target bench_mpi_bed bench_scene_throughput > /dev/null
BENCH="$BUILD/benchmarks/mpi/bench_mpi_bed"
BEDS="$ROOT/out/bench"
mkdir -p "$BEDS"
for scene in A B; do
  for n in 100 50; do
    bed="$BEDS/${scene}${n}k.data"
    [[ -f $bed ]] || "$BUILD/benchmarks/bench_scene_throughput" --scene $scene --particles ${n}000 --threads 2 \
      --prepare "$bed" > "$BEDS/prepare_${scene}${n}k.log"
  done
done
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1  # as root (CI, containers)
CSV="$ROOT/benchmarks/mpi/results/scaling.csv"
commit="$(git -C "$ROOT" rev-parse --short HEAD)"
cpu="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo "# commit=$commit date=$(date -u +%FT%TZ) machine=\"$cpu, $(nproc) logical CPUs\" steps=$STEPS repeat=$REPEAT" > "$CSV"
echo "round,case,scene,particles,ranks,threads,policy,s_per_particle_step,bytes_per_step,messages_per_step,rebuilds_per_run,migration_s_per_rebuild,halo_build_s_per_rebuild,refresh_s_per_step,rebalances,rebalance_s,ghosts_mean,loadavg" >> "$CSV"
# run CASE RANKS THREADS BED [bench_mpi_bed args]
run() {
  local case="$1" ranks="$2" threads="$3" bed="$4"
  shift 4
  local line
  local bind=core
  ((threads == 1)) || bind=none
  line="$(OMP_NUM_THREADS=$threads mpirun --bind-to $bind -np "$ranks" "$BENCH" --data "$bed" --steps "$STEPS" \
    --repeat "$REPEAT" "$@" | grep '^summary ')"
  echo "round $round, $case: ${line#summary }" >&2
  python3 - "$round,$case" "$line" >> "$CSV" <<'PY'
import shlex, sys
case, line = sys.argv[1], sys.argv[2]
kv = dict(t.split('=', 1) for t in shlex.split(line)[1:])
cols = ['scene', 'particles', 'ranks', 'threads', 'policy', 's_per_particle_step', 'bytes_per_step',
        'messages_per_step', 'rebuilds_per_run', 'migration_s_per_rebuild', 'halo_build_s_per_rebuild',
        'refresh_s_per_step', 'rebalances', 'rebalance_s', 'ghosts_mean', 'loadavg']
print(','.join([case] + ['"%s"' % kv.get(c, '') if c == 'loadavg' else kv.get(c, '') for c in cols]))
PY
}
for round in $(seq "$ROUNDS"); do
for scene in A B; do
  big="$BEDS/${scene}100k.data" half="$BEDS/${scene}50k.data"
  run single_1x1 1 1 "$big" --scene $scene --single
  run single_1x2 1 2 "$big" --scene $scene --single
  run mpi_1x1 1 1 "$big" --scene $scene
  run mpi_1x2 1 2 "$big" --scene $scene
  run mpi_2x1 2 1 "$big" --scene $scene
  run weak_mpi_1x1_half 1 1 "$half" --scene $scene
  run rebuilds_mpi_2x1 2 1 "$big" --scene $scene --skin 2e-7 --rebalance 1.0
done
done
python3 - "$CSV" <<'PY'
import csv, sys
best = {}
for r in csv.DictReader(l for l in open(sys.argv[1]) if not l.startswith('#')):
    k = (r['scene'], r['case'])
    if k not in best or float(r['s_per_particle_step']) < float(best[k]['s_per_particle_step']):
        best[k] = r
rows = sorted(best.values(), key=lambda r: r['scene'])
print('| case | scene | N | ranks x threads | ns per particle-step | halo bytes/step | messages/step |')
print('|---|---|---|---|---|---|---|')
for r in rows:
    print('| %s | %s | %s | %s x %s | %.1f | %s | %s |' % (r['case'], r['scene'], r['particles'], r['ranks'],
          r['threads'], 1e9 * float(r['s_per_particle_step']), r['bytes_per_step'], r['messages_per_step']))
PY
