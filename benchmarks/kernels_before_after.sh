#!/usr/bin/env bash
# The contact-law kernels (bench_contact_kernels) of two commits, built alike and run
# interleaved on one core: what a change costs the laws, in particular the laws a scene keeps
# when it selects none of the change's new options (issue 29: "every new option costs nothing
# for a scene that does not select it").
#
# Usage: benchmarks/kernels_before_after.sh [options] REF_BEFORE [REF_AFTER]
#   REF_AFTER defaults to HEAD. Refs are committed states (uncommitted changes are not built).
# Options:
#   --reps N        rounds (default 5); each round runs both binaries once, the order
#                   alternating from round to round
#   --min-time S    Google Benchmark's --benchmark_min_time per kernel [s] (default 0.5)
#   --filter REGEX  --benchmark_filter, applied to each binary's own names (default: every kernel)
#   --core C        the core to pin the runs to with taskset (default: the last online core)
#   --dir DIR       work directory (default: out/kernels_before_after)
#   --jobs J        build jobs (default 1)
#   --map OLD=NEW   a model named OLD in REF_BEFORE is the law named NEW in REF_AFTER (repeatable)
#   --keep          keep the source worktrees and build trees
#   --rebuild       build again although DIR/bin holds a binary of that commit
# The models renamed by a commit between the two refs are mapped without --map:
#   6b651a2 made the default HertzMindlin the potential form and kept the former law as
#   HertzMindlinIncremental, so HertzMindlin before 6b651a2 = HertzMindlinIncremental after.
#
# Each commit is checked out in a git worktree DIR/src-<commit>, configured as in
# docs/performance.md "Machines and method" (Release, -DGRANULE_NATIVE=ON, benchmarks on, tests
# and examples off) in DIR/build-<commit>, and bench_contact_kernels is copied to
# DIR/bin/bench_contact_kernels-<commit>; worktree and build tree are removed at the end
# (--keep keeps them). Runs write DIR/runs/<before|after>-<round>.json.
# Output: DIR/kernels.csv, one row per kernel and ref:
#   kernel,ref,commit,benchmark,ns_per_contact_min,ns_per_contact_median,reps
# (kernel: the name in REF_AFTER; benchmark: the name in that ref; ns per contact evaluation
# from items_per_second, i.e. CPU time), and Markdown tables on stdout: every kernel by its
# name, then the renamed laws side by side.
set -euo pipefail

die() { echo "kernels_before_after.sh: $*" >&2; exit 2; }

reps=5 min_time=0.5 filter="" core="" dir="" jobs=1 keep=0 rebuild=0
maps=()
refs=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --reps) reps="${2:-}"; shift 2 ;;
    --min-time) min_time="${2:-}"; shift 2 ;;
    --filter) filter="${2:-}"; shift 2 ;;
    --core) core="${2:-}"; shift 2 ;;
    --dir) dir="${2:-}"; shift 2 ;;
    --jobs) jobs="${2:-}"; shift 2 ;;
    --map) maps+=("${2:-}"); shift 2 ;;
    --keep) keep=1; shift ;;
    --rebuild) rebuild=1; shift ;;
    -h|--help) sed -n '2,33p' "$0"; exit 0 ;;
    -*) die "unknown option $1 (see --help)" ;;
    *) refs+=("$1"); shift ;;
  esac
done
[[ ${#refs[@]} -ge 1 && ${#refs[@]} -le 2 ]] || die "give REF_BEFORE [REF_AFTER] (see --help)"
[[ "$reps" =~ ^[1-9][0-9]*$ ]] || die "--reps must be a positive integer"
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || die "--jobs must be a positive integer"
command -v taskset > /dev/null || die "taskset (util-linux) is needed"
command -v python3 > /dev/null || die "python3 is needed"

repo="$(git -C "$(dirname "$0")" rev-parse --show-toplevel)" || die "the script must sit in a git checkout of granule"
ref_before="${refs[0]}"
ref_after="${refs[1]:-HEAD}"
commit_before="$(git -C "$repo" rev-parse --verify "$ref_before^{commit}")" || die "unknown ref $ref_before"
commit_after="$(git -C "$repo" rev-parse --verify "$ref_after^{commit}")" || die "unknown ref $ref_after"
short_before="$(git -C "$repo" rev-parse --short "$commit_before")"
short_after="$(git -C "$repo" rev-parse --short "$commit_after")"
[[ -n "$core" ]] || core="$(( $(nproc) - 1 ))"
[[ -n "$dir" ]] || dir="$repo/out/kernels_before_after"
mkdir -p "$dir/bin" "$dir/runs"
dir="$(cd "$dir" && pwd)"

# Renames between the refs: 6b651a2 (HertzMindlin -> HertzMindlinIncremental).
is_ancestor() { git -C "$repo" merge-base --is-ancestor "$1" "$2" 2> /dev/null; }
if git -C "$repo" rev-parse --verify --quiet 6b651a2^{commit} > /dev/null &&
   is_ancestor 6b651a2 "$commit_after" && ! is_ancestor 6b651a2 "$commit_before"; then
  maps+=("HertzMindlin=HertzMindlinIncremental")
fi

worktrees=()
cleanup() {
  if [[ $keep -eq 0 ]]; then
    for w in "${worktrees[@]}"; do
      git -C "$repo" worktree remove --force "$w" > /dev/null 2>&1 || true
      rm -rf "$dir/build-$(basename "$w" | sed 's/^src-//')"
    done
  fi
}
trap cleanup EXIT

build() {  # commit -> path of its binary
  local commit="$1" short bin src bld
  short="$(git -C "$repo" rev-parse --short "$commit")"
  bin="$dir/bin/bench_contact_kernels-$short"
  if [[ -x "$bin" && $rebuild -eq 0 ]]; then
    echo "$bin"
    return
  fi
  src="$dir/src-$short"
  bld="$dir/build-$short"
  if [[ ! -d "$src" ]]; then
    git -C "$repo" worktree add --detach "$src" "$commit" > /dev/null 2>&1 || die "git worktree add $src failed"
  fi
  echo "building bench_contact_kernels at $short in $bld" >&2
  cmake -S "$src" -B "$bld" -DCMAKE_BUILD_TYPE=Release -DGRANULE_BUILD_BENCHMARKS=ON -DGRANULE_NATIVE=ON \
        -DGRANULE_BUILD_TESTS=OFF -DGRANULE_BUILD_EXAMPLES=OFF > "$dir/cmake-$short.log" 2>&1 ||
    die "cmake configure at $short failed (see $dir/cmake-$short.log)"
  cmake --build "$bld" -j "$jobs" --target bench_contact_kernels >> "$dir/cmake-$short.log" 2>&1 ||
    die "build at $short failed (see $dir/cmake-$short.log)"
  cp "$bld/benchmarks/bench_contact_kernels" "$bin"
  echo "$bin"
}

# build() runs in a command substitution (a subshell): its worktree is recorded here instead.
bin_before="$(build "$commit_before")"
[[ -d "$dir/src-$short_before" ]] && worktrees+=("$dir/src-$short_before")
bin_after="$(build "$commit_after")"
[[ -d "$dir/src-$short_after" ]] && worktrees+=("$dir/src-$short_after")

load_start="$(cut -d' ' -f1-3 /proc/loadavg)"
args=(--benchmark_min_time="$min_time" --benchmark_out_format=json)
[[ -n "$filter" ]] && args+=(--benchmark_filter="$filter")
rm -f "$dir"/runs/*.json
for ((r = 1; r <= reps; ++r)); do
  if (( r % 2 == 1 )); then order=(before after); else order=(after before); fi
  for which in "${order[@]}"; do
    if [[ $which == before ]]; then bin="$bin_before"; else bin="$bin_after"; fi
    echo "round $r/$reps: $which" >&2
    OMP_NUM_THREADS=1 taskset -c "$core" "$bin" "${args[@]}" --benchmark_out="$dir/runs/$which-$r.json" \
      > /dev/null 2> "$dir/runs/$which-$r.err" || die "$bin failed (see $dir/runs/$which-$r.err)"
  done
done
load_end="$(cut -d' ' -f1-3 /proc/loadavg)"

python3 - "$dir" "$ref_before" "$short_before" "$ref_after" "$short_after" "$reps" "$min_time" "$core" \
  "$load_start" "$load_end" "${maps[@]}" <<'EOF'
import csv, glob, json, os, statistics, sys

dir_, ref_b, c_b, ref_a, c_a, reps, min_time, core, load0, load1 = sys.argv[1:11]
maps = dict(m.split("=", 1) for m in sys.argv[11:])  # model name before -> after

def read(which):
    runs = {}
    for f in sorted(glob.glob(os.path.join(dir_, "runs", which + "-*.json"))):
        with open(f) as fh:
            for b in json.load(fh)["benchmarks"]:
                if b.get("run_type", "iteration") != "iteration" or "items_per_second" not in b:
                    continue
                runs.setdefault(b["name"], []).append(1e9 / b["items_per_second"])
    return runs

before, after = read("before"), read("after")

def renamed(name, old, new):  # evaluate/3D/<model>/4096 with <model> = old -> new
    parts = name.split("/")
    return "/".join(new if (k == len(parts) - 2 and p == old) else p for k, p in enumerate(parts))

def stats(v):
    return (min(v), statistics.median(v)) if v else (None, None)

rows = []
with open(os.path.join(dir_, "kernels.csv"), "w", newline="") as fh:
    w = csv.writer(fh)
    w.writerow(["kernel", "ref", "commit", "benchmark", "ns_per_contact_min", "ns_per_contact_median", "reps"])
    for name, v in sorted(after.items()):
        w.writerow([name, ref_a, c_a, name, "%.4g" % min(v), "%.4g" % statistics.median(v), len(v)])
    for name, v in sorted(before.items()):
        w.writerow([name, ref_b, c_b, name, "%.4g" % min(v), "%.4g" % statistics.median(v), len(v)])
    for old, new in maps.items():  # the renamed laws once more, under their name after
        for name, v in sorted(before.items()):
            if name.split("/")[-2:-1] == [old]:
                w.writerow([renamed(name, old, new), ref_b, c_b, name, "%.4g" % min(v),
                            "%.4g" % statistics.median(v), len(v)])

def fmt(x):
    return "–" if x is None else "%.2f" % x

print(f"Contact kernels, ns per contact evaluation (CPU time), min and median of {reps} interleaved "
      f"rounds, --benchmark_min_time={min_time}, pinned to core {core}; before = {ref_b} ({c_b}), "
      f"after = {ref_a} ({c_a}); load average {load0} at the start, {load1} at the end.\n")
if maps:
    print("Same law under another name (after <- before): " +
          ", ".join(f"{new} <- {old}" for old, new in maps.items()) +
          "; the name alone compares different laws for these models (marked *).\n")
print("| kernel | before min | before median | after min | after median | after/before (min) |")
print("|---|---:|---:|---:|---:|---:|")
for name in sorted(set(before) | set(after)):
    b_min, b_med = stats(before.get(name, []))
    a_min, a_med = stats(after.get(name, []))
    ratio = "–" if b_min is None or a_min is None else "%.3f" % (a_min / b_min)
    mark = " *" if name.split("/")[-2:-1] and name.split("/")[-2] in maps else ""
    print(f"| {name}{mark} | {fmt(b_min)} | {fmt(b_med)} | {fmt(a_min)} | {fmt(a_med)} | {ratio} |")
if maps:
    print("\nRenamed laws, the same physics before and after:\n")
    print("| kernel after | kernel before | before min | before median | after min | after median | after/before (min) |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for old, new in maps.items():
        for name in sorted(before):
            if name.split("/")[-2:-1] != [old]:
                continue
            target = renamed(name, old, new)
            b_min, b_med = stats(before[name])
            a_min, a_med = stats(after.get(target, []))
            ratio = "–" if a_min is None else "%.3f" % (a_min / b_min)
            print(f"| {target} | {name} | {fmt(b_min)} | {fmt(b_med)} | {fmt(a_min)} | {fmt(a_med)} | {ratio} |")
print(f"\nCSV: {os.path.join(dir_, 'kernels.csv')}")
EOF
