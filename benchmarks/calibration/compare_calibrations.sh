#!/usr/bin/env bash
# Errors of the MSD model against the FEM on the comparison benchmarks, before
# and after calibration (the three factors, MATERIAL.yaml, and the lattice with
# its edge classes, MATERIAL_lattice.yaml): the calibration targets (uniaxial,
# shear) and the held-out tests (bending under a tip load and under gravity,
# vibration, indentation).
# Usage: benchmarks/calibration/compare_calibrations.sh [OUT_DIR]   (after the build)
# Prints a markdown table (reports/calibration_table.py) of the compare JSONs.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
tb="${TISSUEBENCH:-$root/build/tissuebench}"   # override: TISSUEBENCH=/path/to/binary
out="${1:-calibration_comparison}"
mkdir -p "$out"
for spec in uniaxial shear bending bending_gravity vibration indentation; do
  # Uncalibrated: both solvers (the FEM reference is computed once here).
  if [[ ! -f "$out/uncalibrated/${spec}_compare.json" ]]; then
    "$tb" run "$root/benchmarks/specs/$spec.yaml" --solver both --out "$out/uncalibrated" --quiet
  fi
  # The calibrations of the spec's material (benchmarks/materials.yaml entry).
  material="$(sed -n 's/.*library: *\([A-Za-z_]*\).*/\1/p' "$root/benchmarks/specs/$spec.yaml" | head -n 1)"
  for cal in "$root"/benchmarks/calibration/"$material".yaml "$root"/benchmarks/calibration/"$material"_lattice.yaml; do
    [[ -f "$cal" ]] || continue
    name="$(basename "$cal" .yaml)"
    mkdir -p "$out/$name"
    # A run that blows up is a result too: its failure goes into the table.
    rm -f "$out/$name/${spec}_failure.txt"
    run_spec="$root/benchmarks/specs/$spec.yaml"
    if [[ "$name" == *_lattice ]]; then
      # The fitted lattice's volume term is 4-10 times the shipped one: exact
      # Newton (sparse_lu), as the suite's lattice variant and calibrate's check.
      run_spec="$out/$name/$spec.yaml"
      sed 's/newton_linear_solver: symmetric_ldlt/newton_linear_solver: sparse_lu/' \
        "$root/benchmarks/specs/$spec.yaml" > "$run_spec"
    fi
    if "$tb" run "$run_spec" --solver msd --calibration "$cal" \
         --out "$out/$name/${spec}_msd.h5" --quiet > "$out/$name/${spec}_run.log" 2>&1; then
      "$tb" compare "$out/$name/${spec}_msd.h5" "$out/uncalibrated/${spec}_fem.h5" \
        --json "$out/$name/${spec}_compare.json" > /dev/null
    else
      rm -f "$out/$name/${spec}_compare.json"
      grep -m1 "failed:\|error:" "$out/$name/${spec}_run.log" > "$out/$name/${spec}_failure.txt" || true
    fi
  done
done
/usr/bin/python3 "$root/reports/calibration_table.py" "$out"
