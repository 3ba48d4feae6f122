#!/usr/bin/env bash
# The implicit leg's Newton solve with and without Anderson acceleration of
# its chord steps (msd/include/msd/model/model.hpp, NewtonOptions::
# anderson_depth): the physiological scenes (BDF2 at 1 ms, the symmetric
# LDLT solve, modified Newton) run as shipped but for the depth and a
# shortened duration, one at a time on one thread (they are timed), depth 0
# (plain chord steps, the path it replaces) then depth 3, in the same run.
# Prints per scene and depth: wall seconds per simulated second, Newton
# iterations and factorisations per step, and the knee's end angle (the two
# depths meet the same Newton tolerance, so it agrees far below a degree).
# Usage: bash benchmarks/leg_newton_anderson.sh [OUT_DIR] [DURATION_S] [SCENE ...]
#   (after scripts/test.sh or scripts/main.sh has built the project;
#   TISSUEBENCH=path runs another build). Default: 2 s of hamstrings,
#   quadriceps, drop and wobble; about 6 minutes on this machine.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
tb="${TISSUEBENCH:-$root/build/tissuebench}"
out="${1:-$root/results/leg_newton_anderson}"
duration="${2:-2}"
shift 2 || shift $# || true
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(hamstrings quadriceps drop wobble)
[ -x "$tb" ] || { echo "leg_newton_anderson: $tb: not built (run bash scripts/test.sh first)" >&2; exit 2; }
mkdir -p "$out"
# A summary's field: top level (the run's counters) or among its values; a
# scene with variants writes one summary per variant, DIR/VARIANT/summary.json.
field() { /usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d[sys.argv[2]] if sys.argv[2] in d else d['values'][sys.argv[2]])" "$1" "$2"; }
printf '%-12s %5s %13s %16s %20s %16s\n' scene depth "wall s/sim s" "iterations/step" "factorisations/step" "knee end, deg"
for s in "${scenes[@]}"; do
  extra=()
  [ "$s" = wobble ] && extra=(--set 'variants=[{name: relaxed, activation: {front: 0, back: 0}}]')  # one variant
  for depth in 0 3; do
    dir="$out/${s}_anderson$depth"
    rm -rf "$dir"
    "$tb" leg "$root/msd/data/physiological/$s.yaml" --out "$dir" --obj-every 0 --quiet \
      --set duration="$duration" --set threads=1 --set newton.anderson_depth=$depth "${extra[@]}" > /dev/null
    summary="$dir/summary.json"
    [ -f "$dir/relaxed/summary.json" ] && summary="$dir/relaxed/summary.json"
    steps=$(/usr/bin/python3 -c "print(round($(field "$summary" simulated_seconds) / $(field "$summary" dt)))")
    /usr/bin/python3 -c "import sys; s, d, w, i, f, n, k = sys.argv[1:]; n = float(n); print('%-12s %5s %13.2f %16.2f %20.3f %16.9f' % (s, d, float(w), float(i) / n, float(f) / n, float(k)))" \
      "$s" "$depth" "$(field "$summary" wall_per_simulated_second)" "$(field "$summary" newton_iterations)" \
      "$(field "$summary" factorizations)" "$steps" "$(field "$summary" knee_angle_end_deg)"
  done
done
