#!/usr/bin/env bash
# Reruns the FEM verification cases and refinement studies whose figures are
# recorded in benchmarks/results/2026-11-22-fem-reference.md, printing the tables.
# Usage: bash benchmarks/fem_verification.sh [OUT_DIR]   (after scripts/test.sh
# or scripts/main.sh has built the project). The bonded-cylinder study takes
# about 20 minutes on two cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
tb="$root/build/tissuebench"
out="${1:-$root/results/fem_verification}"
mkdir -p "$out"
specs="$root/benchmarks/specs"
for s in verify_uniaxial_roller verify_uniaxial_roller_incompressible verify_simple_shear \
         verify_cooks_membrane verify_cooks_membrane_incompressible verify_bar_vibration verify_hanging_bar; do
  "$tb" run "$specs/$s.yaml" --solver fem --quiet --out "$out/$s.h5" | head -1
done
/usr/bin/python3 "$root/reports/results_table.py" "$out"/verify_*.h5
"$tb" converge "$specs/verify_cooks_membrane.yaml" --levels 0,1,2 --out "$out/cooks" --quiet
sed -e 's/cells: \[16, 16, 1\]/cells: [8, 8, 1]/' "$specs/verify_cooks_membrane.yaml" > "$out/cooks8.yaml"
"$tb" converge "$out/cooks8.yaml" --levels 0,1,2 --out "$out/cooks" --quiet
"$tb" converge "$specs/verify_cooks_membrane_incompressible.yaml" --levels 0,1,2 --out "$out/cooks_inc" --quiet
"$tb" converge "$specs/uniaxial_reference.yaml" --degree 1 --levels 1,2,3 --out "$out/cylinder" --quiet
"$tb" converge "$specs/uniaxial_reference.yaml" --degree 2 --levels 0,1,2 --out "$out/cylinder" --quiet
