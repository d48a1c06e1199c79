#!/usr/bin/env bash
# The paper-scale study of lunar_shock_channel (README, "Paper-scale study"), in this order:
#   length   loose bed, 0.5 m and 1 m, v_p = 10 and 0.1 m/s: decides the channel length
#   loose    001 table 8's nine piston speeds (0.1 and 10 m/s come from the length check)
#   medium   the medium bed's c_0 (0.01, 0.1 m/s) and its 10 m/s row
#   rolling  the other reading of the rolling damping (eta_r = 0) at 0.1 and 10 m/s
#   bender   the S wave at 10 m/s
# Every case writes its own file under results/<tag>/; a rerun skips the cases done, so the
# script can be stopped and started again. Beds are cached in out/lunar_shock_channel/beds.
# Progress with an ETA goes to the log also off a terminal. At the end report.py regenerates
# the README's tables.
#   examples/lunar_shock_channel/run_study.sh [tag ...]     (default: length loose medium)
#   examples/lunar_shock_channel/run_study.sh --list        (the plan and its estimated cost)
# Environment: THREADS (default 2).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$HERE/../common/study_build.sh"
study_build lunar_shock_channel
OUT="$ROOT/out/lunar_shock_channel"
RES="$HERE/results"
mkdir -p "$OUT"

if [[ "${1:-}" == "--list" ]]; then
  for tag in length loose medium rolling bender; do
    "$EXE" --study "$tag" --list --out "$OUT" --results "$RES" --threads "${THREADS:-2}"
  done
  exit 0
fi

tags=("$@")
((${#tags[@]} > 0)) || tags=(length loose medium)
for tag in "${tags[@]}"; do
  case "$tag" in
    length | loose | medium | rolling | bender)
      echo "== $tag" | tee -a "$OUT/study_$tag.log"
      "$EXE" --study "$tag" --out "$OUT" --results "$RES" --threads "${THREADS:-2}" 2>&1 | tee -a "$OUT/study_$tag.log"
      ;;
    *) echo "unknown study tag '$tag' (length, loose, medium, rolling, bender)" >&2; exit 2 ;;
  esac
done
/usr/bin/python3 "$HERE/report.py"
