#!/usr/bin/env bash
# The paper-scale study of two_rod_intrusion (README, "Paper scale"), in order of importance:
#   square     square rods, 3 beds, s/d = 0,1,2,3,4,5,6,8,11,15 and a single rod
#   cylinder   cylindrical rods, 1 bed (the first square bed: same seed, same bed)
#   rho1774    table I's 1100 kg/m^3 read as the bulk density: grains of 1100/0.62 kg/m^3,
#              cylinders at s/d = 2 and 3 (around its peak), for the paper's W* = 0.55 J
#   box13      the sweep of square rods in a 13 x 13 cm box (the 9 cm box fails its box-size
#              check): s/d = 0 ... 15 and a single rod, 3 beds; s/d = 3 and 15 also check 9 cm
#   box17      the box-size check of the 13 cm box: a 17 x 17 cm box, s/d = 3 and 15, 3 beds
#   box25      the paper's own 25 x 25 cm box (neither smaller box passes its check): one bed,
#              s/d = 3 and 15 first, then 5, 4 and 2 (the peak), 11 and 6 (the plateau and the
#              fall), 0 and 8, on the same (cached) bed
#   legacy9    the law check: LIGGGHTS 3.8's Hertz-Mindlin (HertzMindlinLegacy, the law paper 000
#              ran with; program two_rod_intrusion_legacy) in the 9 cm box, s/d = 3, 4 and 15,
#              3 beds, against `square` (the force history, HertzMindlinIncremental)
# Every case writes its own file under results/<tag>/runs/; a rerun skips the cases done, so the
# script can be stopped and started again. Progress with an ETA goes to the log also off a
# terminal. At the end report.py regenerates README.md's tables and the figures.
#   examples/two_rod_intrusion/run_study.sh [tag ...]     (default: all, in this order)
# Environment: THREADS (default 2).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$HERE/../common/study_build.sh"
ROOT="$(cd "$HERE/../.." && pwd)"
OUT="$ROOT/out/two_rod_study"
RES="$HERE/results"
mkdir -p "$OUT"

run() {
  local tag="$1"
  shift
  local target=two_rod_intrusion
  [[ $tag == legacy9 ]] && target=two_rod_intrusion_legacy
  study_build "$target"
  echo "== $tag: $*" | tee -a "$OUT/$tag.log"
  "$EXE" --study "$tag" --out "$OUT" --results "$RES/$tag" --threads "${THREADS:-2}" "$@" 2>&1 | tee -a "$OUT/$tag.log"
}

tags=("$@")
((${#tags[@]} > 0)) || tags=(square cylinder rho1774 box17 box13)
for tag in "${tags[@]}"; do
  case "$tag" in
    square) run square --seeds 1,2,3 ;;
    cylinder) run cylinder --shape cylinder --seeds 1 ;;
    rho1774) run rho1774 --shape cylinder --seeds 1 --density 1774 --gap-list 2,3 --no-single ;;
    box13) run box13 --seeds 1,2,3 --box 0.13,0.13,0.10 --gap-list 0,1,2,3,4,5,6,8,11,15 ;;
    box17) run box17 --seeds 1,2,3 --box 0.17,0.17,0.10 --gap-list 3,15 --no-single ;;
    box25) run box25 --seeds 1 --box 0.25,0.25,0.10 --gap-list 3,15,5,4,2,11,6,0,8 --no-single ;;
    legacy9) run legacy9 --seeds 1,2,3 --gap-list 3,15,4 --no-single ;;
    *) echo "unknown study tag '$tag' (square, cylinder, rho1774, box13, box17, box25, legacy9)" >&2; exit 2 ;;
  esac
done
/usr/bin/python3 "$HERE/report.py"
