#!/usr/bin/env bash
# The main job on its built-in default: set up, build, run the standard suite's
# quick tier (the comparison benchmarks by the FEM and three MSD variants, a
# small sweep, the extremes, FEM verification), print the error table, and write
# results/ with the report (results/report/index.html and summary.md).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
out="${1:-$TB_ROOT/results}"
"$TB_ROOT/build/tissuebench" suite --tier quick --out "$out"
echo "report: $out/report/index.html"
