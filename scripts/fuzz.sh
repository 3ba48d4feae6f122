#!/usr/bin/env bash
# Fuzzes the file readers with libFuzzer (docs/fuzzing.md). Installs Debian's
# clang and its fuzzer runtime when missing (not part of scripts/setup.sh: only
# this script needs them), builds the targets of tests/fuzz/ in build-fuzz/
# (clang, AddressSanitizer + UndefinedBehaviorSanitizer, without the FEM), and
# runs each for SECONDS from a seed corpus of the shipped files.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]     (default: 60 s each, every target)
#
# Per target: the corpus grows in build-fuzz/corpus/TARGET/, an input that
# crashes, trips a sanitizer, leaks an exception other than msd::Error, hangs
# (> 10 s) or runs away with memory (> 2 GB) is written to
# build-fuzz/findings/TARGET/, the log to build-fuzz/logs/TARGET.log, and one
# line (executions, seconds, corpus size, findings) to build-fuzz/summary.txt.
# Exit status 1 when anything was found. Keep each finding, once fixed, in
# tests/fuzz/regressions/TARGET/ (the fast test fuzz_regressions_test replays it).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
SECONDS_EACH=${1:-60}
shift || true
ALL=(spec calibration baseline activation_script leg_scene mesh_scene obj stl ply)
if [ $# -gt 0 ]; then TARGETS=("$@"); else TARGETS=("${ALL[@]}"); fi
BUILD="$ROOT/build-fuzz"

# clang, libFuzzer's runtime (libclang_rt.fuzzer: only recommended by clang-14)
# and LLVM's OpenMP (msd's force engine) - Debian bookworm's names.
FUZZ_PACKAGES=(clang libclang-rt-14-dev libomp-14-dev)
missing=()
for p in "${FUZZ_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "fuzz: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

mkdir -p "$BUILD"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DTISSUEBENCH_WITH_FEM=OFF -DTISSUEBENCH_FUZZ=ON -DBUILD_TESTING=OFF -DTISSUEBENCH_BUILD_BENCHMARKS=OFF \
  -DTISSUEBENCH_WERROR=OFF >"$BUILD/configure.log" 2>&1 || { cat "$BUILD/configure.log"; exit 2; }
cmake --build "$BUILD" -j"$(nproc)" --target "${TARGETS[@]/#/fuzz_}"

# Seeds: the shipped files of each kind, plus small hand-made surfaces in
# every encoding the readers take (tests/fuzz/seeds/).
seeds() {
  case "$1" in
    spec) echo "$ROOT"/benchmarks/specs/*.yaml ;;
    calibration) echo "$ROOT"/benchmarks/calibration/*.yaml ;;
    baseline) echo "$ROOT"/reports/baselines/*.yaml ;;
    activation_script) echo "$ROOT"/msd/data/scripts/*.txt ;;
    leg_scene) echo "$ROOT"/msd/data/scenes/*.yaml ;;
    mesh_scene) echo "$ROOT"/msd/data/leg/leg.yaml ;;
    obj) echo "$ROOT"/tests/fuzz/seeds/obj/* "$ROOT"/msd/data/leg/*.obj ;;
    stl) echo "$ROOT"/tests/fuzz/seeds/stl/* ;;
    ply) echo "$ROOT"/tests/fuzz/seeds/ply/* ;;
    *) echo "fuzz: no target '$1' (targets: ${ALL[*]})" >&2; exit 2 ;;
  esac
}

found=0
mkdir -p "$BUILD/logs"
for t in "${TARGETS[@]}"; do
  corpus="$BUILD/corpus/$t" findings="$BUILD/findings/$t"
  mkdir -p "$corpus" "$findings"
  # shellcheck disable=SC2046
  cp -n $(seeds "$t") "$corpus/"
  before=$(find "$findings" -type f | wc -l)
  start=$(date +%s)
  # The shipped leg OBJ files (up to 770 kB) are cut to 64 kB: a vertex-rich
  # prefix; every other seed is far smaller.
  "$BUILD/fuzz/fuzz_$t" "$corpus" -max_total_time="$SECONDS_EACH" -timeout=10 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$findings/" >"$BUILD/logs/$t.log" 2>&1 || true
  secs=$(( $(date +%s) - start ))
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$BUILD/logs/$t.log" | grep -o '[0-9]*$' || echo "?")
  after=$(find "$findings" -type f | wc -l)
  line="$t: ${execs} executions in ${secs} s, corpus $(find "$corpus" -type f | wc -l) inputs, $((after - before)) new findings"
  echo "$line" | tee -a "$BUILD/summary.txt"
  if [ "$after" -gt "$before" ]; then
    found=1
    grep -a -m3 -E "ERROR|tbfuzz:|SUMMARY" "$BUILD/logs/$t.log" || true
  fi
done
exit "$found"
