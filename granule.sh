#!/usr/bin/env bash
# granule.sh: install dependencies, build, test, run the main example and benchmark granule.
# Run `./granule.sh help` for the list of commands.
set -euo pipefail

# The example that `./granule.sh run` builds and runs (a folder name under examples/).
MAIN_EXAMPLE=two_rod_intrusion

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
JOBS="${GRANULE_JOBS:-$(nproc 2>/dev/null || echo 2)}"
# "a|b" means either package will do (python3-paraview ships the same `vtk` Python module as
# python3-vtk9 and conflicts with it); the first one is installed when none is present.
DEB_PACKAGES=(build-essential cmake libeigen3-dev catch2 libfftw3-dev libbenchmark-dev libcli11-dev
              python3 python3-numpy python3-matplotlib "python3-vtk9|python3-paraview" pkg-config)
# Only for test-clang (the wide packs compiled by clang, tests/CMakeLists.txt).
DEB_PACKAGES_CLANG=(clang libomp-dev)
# Only for test-mpi (distributed runs, docs/mpi.md).
DEB_PACKAGES_MPI=(libopenmpi-dev openmpi-bin)
# What test-mpi builds: the MPI test programs (tests/CMakeLists.txt, label mpi) and the MPI example.
MPI_TARGETS=(granule_mpi_context granule_mpi_suites 02_pour_settle_mpi)

say() { printf '[granule.sh] %s\n' "$*" >&2; }
die() { say "error: $*"; exit 1; }

usage() {
  cat <<EOF
usage: ./granule.sh <command> [arguments]

  deps                         install the Debian packages granule needs (only if some are missing)
  build [dir] [cmake args...]  configure (Release) and build in dir (default: build/)
  test [ctest args...]         deps + build in build/ + ctest --output-on-failure -j2
  test-sanitize [ctest args...]
                               deps + build with ASan/UBSan (-Og -g1) in build-sanitize/ + ctest
  test-clang [ctest args...]   deps + clang + build the wide-pack tests (-march=native: AVX-512
                               where the machine has it) with clang in build-clang/ + ctest
  test-mpi [ctest args...]     deps + Open MPI + build the MPI tests and example in build-mpi/
                               + ctest -L mpi (distributed runs, docs/mpi.md)
  run [example args...]        deps + build + run the main example ($MAIN_EXAMPLE) in out/<name>/
                               and draw its figures with its plot.py
  bench [benchmark args...]    deps + build with benchmarks and -march=native in build-bench/,
                               then run every Google Benchmark program with these arguments
                               (the scene_* programs are built and listed; they need arguments)
  help                         this text

Environment: GRANULE_JOBS sets the number of parallel compile jobs (default: all cores).
EOF
}

# deps: apt-get install whatever is missing from DEB_PACKAGES; do nothing if all are present.
cmd_deps() {
  install_missing "${DEB_PACKAGES[@]}"
}

# install_missing PACKAGE...: apt-get install those not installed ("a|b": either will do).
install_missing() {
  local packages=("$@")
  if ! command -v dpkg >/dev/null 2>&1; then
    say "not a Debian-based system: make sure these (or equivalents) are installed: ${packages[*]//|/ or }"
    return 0
  fi
  local missing=() entry alternative status found
  for entry in "${packages[@]}"; do
    found=0
    for alternative in ${entry//|/ }; do
      status="$(dpkg -s "$alternative" 2>/dev/null || true)"
      if [[ $status == *"Status: install ok installed"* ]]; then
        found=1
        break
      fi
    done
    ((found == 1)) || missing+=("${entry%%|*}")
  done
  if ((${#missing[@]} == 0)); then
    return 0
  fi
  say "installing missing packages: ${missing[*]}"
  local sudo=()
  if [[ $(id -u) -ne 0 ]]; then
    command -v sudo >/dev/null 2>&1 || die "not root and sudo is not available; install: ${missing[*]}"
    sudo=(sudo)
  fi
  "${sudo[@]}" apt-get update
  "${sudo[@]}" env DEBIAN_FRONTEND="${DEBIAN_FRONTEND:-noninteractive}" \
    apt-get install -y --no-install-recommends "${missing[@]}"
}

# configure_and_build DIR [cmake args...] [-- build args...]: Release unless the args say otherwise.
configure_and_build() {
  local dir="$1"
  shift
  local cmake_args=() build_args=()
  while (($# > 0)) && [[ $1 != -- ]]; do
    cmake_args+=("$1")
    shift
  done
  if (($# > 0)); then
    shift
    build_args=("$@")
  fi
  cmake -S "$ROOT" -B "$dir" -DCMAKE_BUILD_TYPE=Release "${cmake_args[@]}"
  cmake --build "$dir" --parallel "$JOBS" "${build_args[@]}"
}

cmd_build() {
  local dir="$ROOT/build"
  if (($# > 0)) && [[ $1 != -* ]]; then
    dir="$1"
    shift
    [[ $dir == /* ]] || dir="$PWD/$dir"
  fi
  configure_and_build "$dir" "$@"
}

# ctest_env COMMAND...: ctest -j2 runs two test programs at once, each with an OpenMP team of
# two threads on the two cores; waiting threads that spin then take the core from the other
# program. Passive waiting saved 17 % of the CPU time of the 16 slowest sanitizer tests
# (233 -> 193 s, 2026-12-06). A caller's own OMP_WAIT_POLICY wins.
ctest_env() {
  OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}" "$@"
}

cmd_test() {
  cmd_deps
  local start=$SECONDS
  configure_and_build "$ROOT/build"
  say "build/ configured and built in $((SECONDS - start)) s"
  start=$SECONDS
  ctest_env ctest --test-dir "$ROOT/build" --output-on-failure -j2 "$@"
  say "tests passed in $((SECONDS - start)) s"
}

cmd_test_sanitize() {
  cmd_deps
  # -g1 (line tables only): the sanitizers' reports keep file and line, and the build is about a
  # third faster than with -g (test_restitution.cpp: 160 s -> 107 s, objects 95 MB -> 35 MB).
  # -Og instead of -O1: test_packed_contacts.cpp + test_history_rebuild.cpp compiled in 116 s of
  # CPU instead of 266 s, and their tests ran in 122 s instead of 119 s (2026-12-07).
  local start=$SECONDS
  configure_and_build "$ROOT/build-sanitize" -DGRANULE_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug \
    "-DCMAKE_CXX_FLAGS_DEBUG=-Og -g1" -DGRANULE_BUILD_EXAMPLES=OFF
  say "build-sanitize/ configured and built in $((SECONDS - start)) s"
  start=$SECONDS
  ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}" \
  UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}" \
    ctest_env ctest --test-dir "$ROOT/build-sanitize" --output-on-failure -j2 -E '^install_and_consume$' "$@"
  say "sanitizer tests passed in $((SECONDS - start)) s"
}

# test-clang: the packed laws, lanes and transposes (granule_native_tests: core/test_lanes.cpp,
# contact/test_packed_contacts*.cpp) compiled by clang with -march=native. The default build and
# the sanitizers use GCC; under clang with AVX-512, libstdc++ 12's std::experimental::simd once
# blended nothing (core/lanes.hpp, assign_lanes) and every packed law did nothing, which only a
# clang build shows. Builds only that target (about a minute), not the whole suite.
cmd_test_clang() {
  install_missing "${DEB_PACKAGES[@]}" "${DEB_PACKAGES_CLANG[@]}"
  local start=$SECONDS
  configure_and_build "$ROOT/build-clang" -DCMAKE_CXX_COMPILER=clang++ -DGRANULE_BUILD_EXAMPLES=OFF \
    -- --target granule_native_tests
  say "build-clang/ configured and built in $((SECONDS - start)) s"
  start=$SECONDS
  ctest_env ctest --test-dir "$ROOT/build-clang" --output-on-failure -j2 -R '^native:' "$@"
  say "clang tests passed in $((SECONDS - start)) s"
}

# test-mpi: not part of `test` (nor of .ci/run): it needs Open MPI, and the MPI tests run for
# minutes (mpi_distributed_threads_np2 alone, 4 processes, the longest; leave it out with
# `-E threads`). The ctest entries set what mpiexec needs (e.g. as root, more ranks than cores).
# Examples are configured only for the target 02_pour_settle_mpi; nothing else is built.
cmd_test_mpi() {
  install_missing "${DEB_PACKAGES[@]}" "${DEB_PACKAGES_MPI[@]}"
  local start=$SECONDS
  configure_and_build "$ROOT/build-mpi" -DGRANULE_MPI=ON -DGRANULE_BUILD_EXAMPLES=ON \
    -- --target "${MPI_TARGETS[@]}"
  say "build-mpi/ configured and built in $((SECONDS - start)) s"
  start=$SECONDS
  ctest_env ctest --test-dir "$ROOT/build-mpi" --output-on-failure -L mpi "$@"
  say "MPI tests passed in $((SECONDS - start)) s"
}

cmd_run() {
  cmd_deps
  local name="$MAIN_EXAMPLE"
  if [[ -f $ROOT/examples/$MAIN_EXAMPLE/main.cpp ]]; then
    configure_and_build "$ROOT/build" -- --target "$MAIN_EXAMPLE"
  else
    configure_and_build "$ROOT/build" -- --target granule_examples
  fi
  if [[ ! -x $ROOT/build/examples/$MAIN_EXAMPLE ]]; then
    name=""
    local main_cpp candidate
    for main_cpp in "$ROOT"/examples/*/main.cpp; do
      [[ -e $main_cpp ]] || continue
      candidate="$(basename "$(dirname "$main_cpp")")"
      if [[ -x $ROOT/build/examples/$candidate ]]; then
        name="$candidate"
        break
      fi
    done
    [[ -n $name ]] || die "the main example '$MAIN_EXAMPLE' does not exist and no other example is built"
    say "the main example '$MAIN_EXAMPLE' does not exist yet; running the first built example, '$name'"
  fi
  mkdir -p "$ROOT/out/$name"
  say "running $name in out/$name/"
  cd "$ROOT/out/$name"
  "$ROOT/build/examples/$name" "$@"
  # The figures (W(s/d) and the others) from the CSVs just written; a help or failed run has
  # none to draw. Debian's python3 has the matplotlib that deps installed.
  local plot="$ROOT/examples/$name/plot.py"
  if [[ -f $plot ]] && compgen -G "*.csv" >/dev/null; then
    say "drawing the figures: $plot"
    /usr/bin/python3 "$plot" . || say "plot.py failed (the CSV results above are complete)"
  fi
}

cmd_bench() {
  cmd_deps
  configure_and_build "$ROOT/build-bench" -DGRANULE_BUILD_BENCHMARKS=ON -DGRANULE_NATIVE=ON \
    -DGRANULE_BUILD_TESTS=OFF -DGRANULE_BUILD_EXAMPLES=OFF
  mkdir -p "$ROOT/out/bench"
  cd "$ROOT/out/bench"
  local source name exe count=0 scenes=()
  for source in "$ROOT"/benchmarks/*.cpp; do
    [[ -e $source ]] || continue
    name="$(basename "$source" .cpp)"
    exe="$ROOT/build-bench/benchmarks/bench_$name"
    [[ -x $exe ]] || die "$exe was not built (is Google Benchmark installed?)"
    if [[ $name == scene_* ]]; then
      scenes+=("$exe")
      continue
    fi
    say "running bench_$name"
    "$exe" "$@"
    count=$((count + 1))
  done
  if ((count == 0)); then
    say "benchmarks/ holds no Google Benchmark programs yet"
  fi
  if ((${#scenes[@]} > 0)); then
    say "scene programs take their own arguments (see benchmarks/README.md) and were not run:"
    printf '  %s\n' "${scenes[@]}" >&2
  fi
}

main() {
  local command="${1:-help}"
  (($# == 0)) || shift
  case "$command" in
    deps) cmd_deps ;;
    build) cmd_build "$@" ;;
    test) cmd_test "$@" ;;
    test-sanitize) cmd_test_sanitize "$@" ;;
    test-clang) cmd_test_clang "$@" ;;
    test-mpi) cmd_test_mpi "$@" ;;
    run) cmd_run "$@" ;;
    bench) cmd_bench "$@" ;;
    help | -h | --help) usage ;;
    *)
      usage >&2
      die "unknown command '$command'"
      ;;
  esac
}

main "$@"
