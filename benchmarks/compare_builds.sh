#!/usr/bin/env bash
# Compares two or more builds of bench_scene_throughput on one settled bed, in the three ways
# that gave consistent answers on a host whose speed swings by +-20 % within minutes
# (docs/performance.md, "Beds larger than the cache" and "The wall walk by entries"):
#
#   end state     after STATE_STEPS steps on one thread, compared byte for byte with the first
#                 build's (`same` or `differs`): a change meant to be exact must say `same`;
#   instructions  per particle-step, from callgrind (valgrind): the instructions of a run of
#                 CG_STEPS + 30 steps less those of a run of CG_STEPS steps, divided by 30 x
#                 particles, so that reading the bed and building the list cancel. Independent
#                 of the host's speed, so differences of 1 % are real -- but they are
#                 instructions, not time;
#   speed         ROUNDS rounds, the builds alternating inside each round, each process the
#                 best of 5 timed runs of STEPS steps pinned to one core (`taskset -c CORE`);
#                 printed per round, then the best and the median of the rounds per build.
#
# Usage: benchmarks/compare_builds.sh --scene A|B --data FILE [options] BIN1 BIN2 [BIN...]
#   --steps N        timed steps per run (default 200; 60 suits a 100k bed)
#   --rounds N       speed rounds (default 5; 0 skips the timing)
#   --core N         core to pin the timed runs to (default 0)
#   --no-callgrind   skip the instruction counts
#   --no-state       skip the end-state comparison
# Environment: CG_STEPS (default 10), STATE_STEPS (default 300).
# Output goes to stdout; work files to a temporary directory that is removed at the end.
set -euo pipefail

die() { echo "compare_builds.sh: $*" >&2; exit 2; }

scene="" data="" steps=200 rounds=5 core=0 callgrind=1 state=1
bins=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --scene) scene="${2:-}"; shift 2 ;;
    --data) data="${2:-}"; shift 2 ;;
    --steps) steps="${2:-}"; shift 2 ;;
    --rounds) rounds="${2:-}"; shift 2 ;;
    --core) core="${2:-}"; shift 2 ;;
    --no-callgrind) callgrind=0; shift ;;
    --no-state) state=0; shift ;;
    -h|--help) sed -n '2,27p' "$0"; exit 0 ;;
    -*) die "unknown option $1 (see --help)" ;;
    *) bins+=("$1"); shift ;;
  esac
done
[[ "$scene" == A || "$scene" == B ]] || die "--scene must be A or B, got '${scene}'"
[[ -r "$data" ]] || die "--data: no readable bed file '${data}' (make one with bench_scene_throughput --prepare)"
[[ "$steps" =~ ^[1-9][0-9]*$ ]] || die "--steps must be a positive integer, got '${steps}'"
[[ "$rounds" =~ ^[0-9]+$ ]] || die "--rounds must be a non-negative integer, got '${rounds}'"
[[ "$core" =~ ^[0-9]+$ ]] || die "--core must be a core number, got '${core}'"
[[ ${#bins[@]} -ge 2 ]] || die "give at least two builds of bench_scene_throughput to compare"
for b in "${bins[@]}"; do [[ -x "$b" ]] || die "'$b' is not an executable"; done
cg_steps="${CG_STEPS:-10}"
state_steps="${STATE_STEPS:-300}"
if [[ $callgrind == 1 ]] && ! command -v valgrind > /dev/null; then
  die "valgrind not found (apt-get install -y valgrind), or pass --no-callgrind"
fi
if [[ $rounds -gt 0 ]] && ! command -v taskset > /dev/null; then
  die "taskset not found (util-linux), or pass --rounds 0"
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
run() { "$1" --scene "$scene" --data "$data" --threads 1 "${@:2}"; }
# Builds are named by their position on the command line (#1, #2, ...): two builds often share
# their file name and the last folders of their path (build-a/benchmarks/..., build-b/...).
name() { echo "#$(($1 + 1))"; }
ir() { sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$1"; }

particles="$(run "${bins[0]}" --steps 1 --warmup 0 --repeat 1 2> "$work/first.log" |
             sed -n 's/^scene=.* particles=\([0-9]*\) .*/\1/p' | head -1)" || particles=""
[[ -n "$particles" ]] || die "'${bins[0]}' printed no summary line on ${data}: $(tail -2 "$work/first.log")"
echo "# scene ${scene}, ${particles} particles, bed ${data}, $(date -u '+%Y-%m-%d %H:%M UTC')"
for k in "${!bins[@]}"; do echo "# build $(name "$k"): ${bins[$k]}"; done

if [[ $state == 1 ]]; then
  echo "# end state after ${state_steps} steps (byte comparison with the first build)"
  for k in "${!bins[@]}"; do
    run "${bins[$k]}" --steps "$state_steps" --warmup 0 --repeat 1 --end-state "$work/state$k" > /dev/null 2>&1 ||
      die "'${bins[$k]}' failed writing its end state"
    verdict=reference
    [[ $k -gt 0 ]] && { cmp -s "$work/state0" "$work/state$k" && verdict=same || verdict=differs; }
    echo "state $(name "$k") $verdict"
  done
fi

if [[ $callgrind == 1 ]]; then
  echo "# instructions per particle-step (callgrind, ${cg_steps} + 30 steps less ${cg_steps})"
  for k in "${!bins[@]}"; do
    pids=()
    for s in "$cg_steps" $((cg_steps + 30)); do
      valgrind --tool=callgrind --callgrind-out-file="$work/cg$k.$s" \
        "${bins[$k]}" --scene "$scene" --data "$data" --threads 1 --steps "$s" --warmup 0 --repeat 1 \
        > /dev/null 2> "$work/cg$k.$s.log" &
      pids+=($!)
    done
    for pid in "${pids[@]}"; do
      # valgrind cannot run AVX-512 code (SIGILL): count instructions on an AVX2 build.
      wait "$pid" || die "'${bins[$k]}' failed under callgrind ($(grep -m1 -o 'unhandled instruction.*\|Illegal.*' "$work"/cg$k.*.log || echo 'see valgrind'));" \
        "valgrind cannot run AVX-512 code: compare builds made with -march=x86-64-v3 (AVX2), or pass --no-callgrind"
    done
    lo="$(ir "$work/cg$k.$cg_steps.log")" hi="$(ir "$work/cg$k.$((cg_steps + 30)).log")"
    [[ -n "$lo" && -n "$hi" ]] || die "callgrind gave no count for '${bins[$k]}' (see valgrind's output)"
    awk -v a="$lo" -v b="$hi" -v n="$particles" -v w="$(name "$k")" \
      'BEGIN { printf "instructions %s %.1f\n", w, (b - a) / (30 * n) }'
  done
fi

if [[ $rounds -gt 0 ]]; then
  echo "# speed: particle-steps/s, best of 5 runs of ${steps} steps per process, core ${core}"
  for r in $(seq "$rounds"); do
    for k in "${!bins[@]}"; do
      v="$(taskset -c "$core" "${bins[$k]}" --scene "$scene" --data "$data" --threads 1 --steps "$steps" \
             --warmup 20 --repeat 5 2> /dev/null |
           sed -n 's/.*particle_steps_per_s_run=\([0-9.e+]*\).*/\1/p' | sort -g | tail -1)" || v=""
      echo "round $r $(name "$k") $v" | tee -a "$work/speed"
    done
  done
  for k in "${!bins[@]}"; do
    sorted="$(awk -v b="$(name "$k")" '$3 == b && $4 != "" { print $4 }' "$work/speed" | sort -g)"
    [[ -n "$sorted" ]] || { echo "speed $(name "$k") no timed run finished"; continue; }
    echo "$sorted" | awk -v w="$(name "$k")" '{ x[NR] = $1 }
      END { m = NR % 2 ? x[(NR + 1) / 2] : 0.5 * (x[NR / 2] + x[NR / 2 + 1]);
            printf "speed %s best %.4g median %.4g (%d rounds)\n", w, x[NR], m, NR }'
  done
fi
