# Sourced by the examples' run_study.sh scripts: the one build every study runs with.
#   study_build TARGET    installs missing packages (granule.sh deps), configures build-native/
#                         (Release, -march=native, no tests) and builds TARGET; sets ROOT, BUILD
#                         and EXE (the program's path).
study_build() {
  ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
  BUILD="$ROOT/build-native"
  "$ROOT/granule.sh" deps
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DGRANULE_NATIVE=ON -DGRANULE_BUILD_TESTS=OFF >/dev/null
  cmake --build "$BUILD" --parallel 2 --target "$1"
  EXE="$BUILD/examples/$1"
}
