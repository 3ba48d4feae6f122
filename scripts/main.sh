#!/usr/bin/env bash
# The main job on its built-in default: set up, build, run the standard suite
# (today: the thesis' three uni-axial experiments), print the summary table and
# write results/ (HDF5 + CSV per experiment, and a figure).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
out="${1:-$TB_ROOT/results}"
"$TB_ROOT/build/tissuebench" suite --out "$out"
/usr/bin/python3 "$TB_ROOT/reports/plot_uniaxial.py" "$out/uniaxial_thesis.png" \
  "$out/uniaxial_thesis_naive.h5" "$out/uniaxial_thesis_repulsion.h5" "$out/uniaxial_thesis_full.h5"
echo "figure: $out/uniaxial_thesis.png"
