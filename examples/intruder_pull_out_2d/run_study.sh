#!/usr/bin/env bash
# The convergence study of intruder_pull_out_2d (issue 27; README, "Convergence"):
#   dtcheck      the quick cell at E = 6e8 Pa, V = 20 mm/s, pulled from one bed with the engine's
#                step and with 002's dt_c / 60
#   convergence  002's cell: E = 6e7 ... 1.8e9 Pa at V = 20 mm/s, V = 20 ... 1.2 mm/s at
#                E = 6e8 Pa, E = 1.8e9 Pa at 6 mm/s, four more beds at the cheapest point
#                (`--study convergence --list` prints the cases and their estimated cost; the
#                README's cost table has what each took)
# Within a tag the program runs the cases in order of their estimated cost, printing each
# estimate first; every case writes its own directory under results/<tag>/ and a rerun skips the
# cases done, so the script can be stopped and started again. Beds are cached in
# out/intruder_pull_out_2d_study/beds/ (a bed serves every speed of its stiffness). Progress with
# an ETA goes to the log also off a terminal. At the end report.py regenerates README.md's tables
# and draws the figures into out/intruder_pull_out_2d_study/figures/.
#   modes        the program's quick and medium modes (one thread, seed 1): their summary.csv
#                goes to results/modes/<mode>/ for the README's "Measured: quick and medium
#                modes" table (rerun after a change of the engine's 2D arithmetic: delete them)
#   examples/intruder_pull_out_2d/run_study.sh [tag ...]     (default: dtcheck convergence)
# Environment: THREADS (default 1: the engine runs the 1600 disks on one thread; more threads
# only speed up the coarse-graining), CASES (comma-separated case names of the one tag given:
# run only those).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$HERE/../common/study_build.sh"
study_build intruder_pull_out_2d
OUT="$ROOT/out/intruder_pull_out_2d_study"
RES="$HERE/results"
mkdir -p "$OUT"

run() {
  local tag="$1"
  local extra=()
  [[ -n "${CASES:-}" ]] && extra=(--cases "$CASES")
  echo "== $tag" | tee -a "$OUT/$tag.log"
  "$EXE" --study "$tag" --out "$OUT" --results "$RES/$tag" --threads "${THREADS:-1}" "${extra[@]}" 2>&1 |
    tee -a "$OUT/$tag.log"
}

tags=("$@")
((${#tags[@]} > 0)) || tags=(dtcheck convergence)
if [[ -n "${CASES:-}" && ${#tags[@]} -ne 1 ]]; then
  echo "CASES needs exactly one tag (its cases are names of that tag)" >&2
  exit 2
fi
# The quick and medium modes as a user runs them; a mode with a summary is skipped.
run_modes() {
  local mode flag
  for mode in quick medium; do
    [[ -f "$RES/modes/$mode/summary.csv" ]] && { echo "== modes: $mode done"; continue; }
    flag=()
    [[ $mode == medium ]] && flag=(--medium)
    echo "== modes: $mode" | tee -a "$OUT/modes.log"
    OMP_NUM_THREADS=1 "$EXE" "${flag[@]}" --out "$OUT/modes/$mode" 2>&1 | tee -a "$OUT/modes.log"
    mkdir -p "$RES/modes/$mode"
    cp "$OUT/modes/$mode/summary.csv" "$RES/modes/$mode/summary.csv"
  done
}
for tag in "${tags[@]}"; do
  case "$tag" in
    dtcheck | convergence) run "$tag" ;;
    modes) run_modes ;;
    *) echo "unknown study tag '$tag' (dtcheck, convergence, modes)" >&2; exit 2 ;;
  esac
done
/usr/bin/python3 "$HERE/report.py"
