#!/usr/bin/env bash
# The shipped leg scenes with real tendons (issue 16's target): every tendon
# at 1.2 GPa (Maganaris & Paul 1999; benchmarks/materials.yaml's tendon, no
# softening, no per-tendon override), everything else as shipped, on two
# threads, stepped three ways:
#   E   symplectic Euler at the scene's step (2e-4 s; the shipped integrator),
#   E2  symplectic Euler at half of it (1e-4 s),
#   I   imex_euler at the scene's step (the strands' stiffness implicit,
#       msd/integrate/imex_strands.hpp),
# and, for the hamstrings only, BDF2 with the symmetric LDLT solve at 5e-3 s.
# Runs one at a time (they are timed), then prints each run's status, its
# knee-angle range and its wall seconds per simulated second.
# Usage: bash benchmarks/leg_real_tendons.sh [OUT_DIR] [SCENE ...]
#   (after scripts/test.sh or scripts/main.sh has built the project;
#   TISSUEBENCH=path runs another build). About 7 minutes on two cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
tb="${TISSUEBENCH:-$root/build/tissuebench}"
out="${1:-$root/results/leg_real_tendons}"
shift || true
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(gravity pretension hamstrings quadriceps co_contraction external_object obstacle drop wobble swing)
mkdir -p "$out"
data="$root/msd/data"
variant() {  # scene name, variant name, step, integrator, extra line
  local src="$data/scenes/$1.yaml" dst="$out/$1_$2.yaml"
  sed -e "s|\.\./scripts/|$data/scripts/|" -e "s|\.\./leg/|$data/leg/|" \
      -e "s|^  modulus: [0-9.e+-]*.*|  modulus: 1.2e9   # real tendon (benchmarks/leg_real_tendons.sh)|" -e "/^  moduli: /d" \
      -e "s|^dt: .*|dt: $3\nthreads: 2\nintegrator: $4${5:+\n$5}|" "$src" > "$dst"
  grep -q "^  modulus: 1.2e9" "$dst" || { echo "leg_real_tendons: $src: no tendon modulus line" >&2; exit 2; }
  [ "$(grep -c '^dt: ' "$dst")" = 1 ] || { echo "leg_real_tendons: $src: no single dt line" >&2; exit 2; }
}
for s in "${scenes[@]}"; do
  variant "$s" E 2.0e-4 symplectic_euler
  variant "$s" E2 1.0e-4 symplectic_euler
  variant "$s" I 2.0e-4 imex_euler
  [ "$s" = hamstrings ] && variant "$s" B 5.0e-3 bdf2 "newton: {linear_solver: symmetric_ldlt}"
done
for f in "$out"/*_{E,E2,I,B}.yaml; do
  [ -f "$f" ] || continue
  n=$(basename "$f" .yaml)
  "$tb" leg "$f" --out "$out/out_$n" --obj-every 0 --quiet > "$out/log_$n.txt" 2>&1 || true
done
python3 - "$out" "${scenes[@]}" <<'PY'
import json, os, sys
out, scenes = sys.argv[1], sys.argv[2:]
for scene in scenes:
    for v in ("E", "E2", "I", "B"):
        d = os.path.join(out, f"out_{scene}_{v}")
        if not os.path.isdir(d):
            continue
        # A scene with variants writes one folder per variant (and an index at the top).
        runs = [os.path.join(d, r) for r in sorted(os.listdir(d)) if os.path.isfile(os.path.join(d, r, "summary.json"))]
        if not runs and os.path.isfile(os.path.join(d, "summary.json")):
            runs = [d]
        for r in runs:
            s = json.load(open(os.path.join(r, "summary.json")))
            m = s.get("values", {})
            status = s.get("status", "?")
            extra = f" ({s.get('failure', '')})" if status != "complete" else ""
            strain = max((val for k, val in m.items() if k.startswith("tendon_") and k.endswith("_strain_max")), default=float("nan"))
            name = f"{scene} {v}" + (f" {os.path.basename(r)}" if r != d else "")
            print(f"{name}: {status}{extra} at {s.get('simulated_seconds', 0):.2f} s; knee {m.get('knee_angle_min_deg', float('nan')):.1f}"
                  f"..{m.get('knee_angle_max_deg', float('nan')):.1f} deg; largest tendon strain {strain:.4f};"
                  f" {s.get('wall_per_simulated_second', float('nan')):.2f} wall s per simulated s")
PY
