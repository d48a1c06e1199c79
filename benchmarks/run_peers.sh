#!/usr/bin/env bash
# Scene-throughput comparison of granule with its peers LIGGGHTS and LAMMPS (issue 6).
#
# Every code starts from the same settled bed (a LAMMPS data file written by granule with
# granule::io::write_lammps_data), runs STEPS timed steps on 1..N cores, and reports
#   code,scene,particles,cores,steps,seconds,particle_steps_per_s,contacts,mean_overlap
# as CSV on stdout (logs and end states go to OUT_DIR). contacts / mean_overlap are the
# particle-particle contacts of the end state and their mean overlap [m], computed for all
# codes by the same tool (benchmarks/peers/contact_stats.cpp), so they compare like with like.
#
# Usage: benchmarks/run_peers.sh --data-A FILE --data-B FILE [options]
#   --data-A FILE     settled bed for scene A (lunar bed, periodic in x)
#   --data-B FILE     settled bed for scene B (intrusion bed, closed box)
#   --scenes "A B"    scenes to run (default: those with a data file)
#   --cores "1 2"     core counts (MPI ranks for the peers, OpenMP threads for granule)
#   --steps N         timed steps per run (default 2000)
#   --codes "liggghts lammps granule"   codes to run (default: all found)
#   --out-dir DIR     logs and end states (default out/peers/runs under the repository)
#   --rounds N        repeat everything N times (default 1), codes interleaved per core count,
#                     so that a slower or faster spell of a shared machine hits all codes alike;
#                     the CSV's last column is the round. benchmarks/peers/summarise.py prints
#                     the best and median of the rounds and the ratios.
# Environment: LIGGGHTS_BIN (liggghts), LAMMPS_BIN (lmp), MPIRUN (mpirun), MPIRUN_FLAGS (extra
# mpirun flags), GRANULE_SCENE_BENCH (granule's scene benchmark; granule is skipped when unset),
# CXX (compiler for contact_stats, g++).
# The Debian 12 builds of LIGGGHTS 3.8 and LAMMPS 29Sep2021 are MPI-only (no OPENMP package),
# so their "cores" are MPI ranks. See benchmarks/peers/README.md.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/.." && pwd)"
peers="$here/peers"

data_A=""; data_B=""; scenes=""; cores="1 2"; steps=2000; codes=""; rounds=1
out_dir="$repo/out/peers/runs"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --data-A) data_A="$2"; shift 2 ;;
    --data-B) data_B="$2"; shift 2 ;;
    --scenes) scenes="$2"; shift 2 ;;
    --cores) cores="$2"; shift 2 ;;
    --steps) steps="$2"; shift 2 ;;
    --codes) codes="$2"; shift 2 ;;
    --out-dir) out_dir="$2"; shift 2 ;;
    --rounds) rounds="$2"; shift 2 ;;
    -h|--help) sed -n '2,27p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "run_peers.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

LIGGGHTS_BIN="${LIGGGHTS_BIN:-liggghts}"
LAMMPS_BIN="${LAMMPS_BIN:-lmp}"
MPIRUN="${MPIRUN:-mpirun}"
MPIRUN_FLAGS="${MPIRUN_FLAGS:-}"
CXX="${CXX:-g++}"
GRANULE_SCENE_BENCH="${GRANULE_SCENE_BENCH:-}"

if [[ -z "$scenes" ]]; then
  [[ -n "$data_A" ]] && scenes="A"
  [[ -n "$data_B" ]] && scenes="$scenes B"
fi
if [[ -z "${scenes// /}" ]]; then echo "run_peers.sh: give --data-A and/or --data-B" >&2; exit 2; fi
if [[ -z "$codes" ]]; then
  command -v "$LIGGGHTS_BIN" >/dev/null && codes="liggghts"
  command -v "$LAMMPS_BIN" >/dev/null && codes="$codes lammps"
  [[ -n "$GRANULE_SCENE_BENCH" ]] && codes="$codes granule"
fi
mkdir -p "$out_dir"

# mpirun as root needs an explicit permission in Open MPI; more ranks than cores need oversubscribe.
mpi_flags="$MPIRUN_FLAGS"
[[ "$(id -u)" == 0 ]] && mpi_flags="$mpi_flags --allow-run-as-root"
max_cores=0; for c in $cores; do (( c > max_cores )) && max_cores=$c; done
(( max_cores > $(nproc) )) && mpi_flags="$mpi_flags --oversubscribe"

# contact_stats: one definition of "contact" and "mean overlap" for every code.
contact_stats="$out_dir/contact_stats"
if [[ ! -x "$contact_stats" || "$peers/contact_stats.cpp" -nt "$contact_stats" ]]; then
  "$CXX" -std=c++20 -O2 -I"$repo/include" -I/usr/include/eigen3 \
    "$peers/contact_stats.cpp" -o "$contact_stats"
fi

scene_data() { if [[ "$1" == A ]]; then echo "$data_A"; else echo "$data_B"; fi; }
scene_periodic() { if [[ "$1" == A ]]; then echo 100; else echo 000; fi; }

# Prints "contacts,mean_overlap" of a data file (NA,NA if there is none).
end_state_stats() {
  local file="$1" periodic="$2" line
  if [[ -s "$file" ]] && line="$("$contact_stats" "$file" "$periodic")"; then
    local c m
    c="$(sed -n 's/.*contacts=\([^ ]*\).*/\1/p' <<<"$line")"
    m="$(sed -n 's/.*mean_overlap=\([^ ]*\).*/\1/p' <<<"$line")"
    echo "$c,$m"
  else
    echo "NA,NA"
  fi
}

# Runs one peer (liggghts or lammps) and prints its CSV row.
run_peer() {
  local code="$1" scene="$2" np="$3" data="$4"
  local tag="${code}_${scene}_np${np}_r${round}" bin input
  local log="$out_dir/$tag.log" end="$out_dir/$tag.end.data"
  if [[ "$code" == liggghts ]]; then bin="$LIGGGHTS_BIN"; input="$peers/liggghts_$scene.in"
  else bin="$LAMMPS_BIN"; input="$peers/lammps_$scene.in"; fi
  rm -f "$end"
  # shellcheck disable=SC2086
  if ! "$MPIRUN" $mpi_flags -np "$np" "$bin" -in "$input" -log none -echo none \
       -var data "$data" -var steps "$steps" -var out "$end" >"$log" 2>&1; then
    echo "run_peers.sh: $tag failed, see $log" >&2
    echo "$code,$scene,NA,$np,$steps,NA,NA,NA,NA"
    return 0
  fi
  # The timed loop is the first "Loop time of X on P procs for N steps with M atoms" after
  # the marker printed just before it (LIGGGHTS appends ", finish time ...").
  local loop
  loop="$(awk '/PEER_TIMED_RUN_BEGIN/ {m=1; next} m && /^Loop time of/ {print; exit}' "$log")"
  local seconds n_steps atoms
  seconds="$(awk '{print $4}' <<<"$loop")"
  n_steps="$(awk '{print $9}' <<<"$loop")"
  atoms="$(awk '{print $12}' <<<"$loop" | tr -d ',')"
  local rate
  rate="$(awk -v n="$atoms" -v s="$n_steps" -v t="$seconds" 'BEGIN {printf "%.4e", n*s/t}')"
  local stats pairs
  stats="$(end_state_stats "$end" "$(scene_periodic "$scene")")"
  pairs="$(sed -n 's/^PEER_CONTACT_PAIRS \([0-9]*\).*/\1/p' "$log" | tail -n 1)"
  if [[ -n "$pairs" && "${stats%%,*}" != "$pairs" ]]; then
    echo "run_peers.sh: $tag: contact/atom says $pairs pairs, contact_stats ${stats%%,*}" >&2
  fi
  echo "$code,$scene,$atoms,$np,$n_steps,$seconds,$rate,$stats"
}

# Hook for granule's own scene benchmark. Contract (benchmarks/peers/README.md):
#   "$GRANULE_SCENE_BENCH" --scene S --data FILE --steps N --threads T
# reads the data file, runs N timed steps with T OpenMP threads and prints a line of
# space-separated key=value pairs containing particle_steps_per_s=R; optional keys seconds=,
# particles=, and end_state=PATH (a data file of the end state, from write_lammps_data).
run_granule() {
  local scene="$1" threads="$2" data="$3"
  local tag="granule_${scene}_t${threads}_r${round}" log
  log="$out_dir/$tag.log"
  if ! OMP_NUM_THREADS="$threads" "$GRANULE_SCENE_BENCH" --scene "$scene" --data "$data" \
       --steps "$steps" --threads "$threads" --end-state "$out_dir/$tag.end.data" >"$log" 2>&1; then
    echo "run_peers.sh: $tag failed, see $log" >&2
    echo "granule,$scene,NA,$threads,$steps,NA,NA,NA,NA"
    return 0
  fi
  local line
  line="$(grep -m1 'particle_steps_per_s=' "$log" || true)"
  get() { sed -n "s/.*\\b$1=\\([^ ]*\\).*/\\1/p" <<<"$line"; }
  local rate seconds particles end stats
  rate="$(get particle_steps_per_s)"; seconds="$(get seconds)"; particles="$(get particles)"
  end="$(get end_state)"
  stats="$(end_state_stats "${end:-/nonexistent}" "$(scene_periodic "$scene")")"
  echo "granule,$scene,${particles:-NA},$threads,$steps,${seconds:-NA},${rate:-NA},$stats"
}

echo "code,scene,particles,cores,steps,seconds,particle_steps_per_s,contacts,mean_overlap,round"
for ((round = 1; round <= rounds; ++round)); do
  for scene in $scenes; do
    data="$(scene_data "$scene")"
    [[ -s "$data" ]] || { echo "run_peers.sh: no data file for scene $scene" >&2; exit 2; }
    for c in $cores; do
      for code in $codes; do
        case "$code" in
          liggghts|lammps) row="$(run_peer "$code" "$scene" "$c" "$data")" ;;
          granule) row="$(run_granule "$scene" "$c" "$data")" ;;
          *) echo "run_peers.sh: unknown code $code" >&2; exit 2 ;;
        esac
        echo "$row,$round"
      done
    done
  done
done
