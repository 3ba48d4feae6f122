#!/usr/bin/env bash
# Reruns the skin study recorded in docs/leg-motion.md ("The skin"): five
# shipped scenes with
#   A  their own constants (five times benchmarks/materials.yaml's flesh and muscle),
#   B  the materials file's flesh (2,990 Pa) and passive muscle (14,950 Pa),
#   C  B plus the skin membrane at the materials file's skin (129 kPa, 1.55 mm),
#   D  B plus a stiffer skin (420 kPa, 1.55 mm; a sensitivity check),
# everything else as shipped, then prints each run's outcome and its wall time.
# Usage: bash benchmarks/leg_skin_study.sh [OUT_DIR]   (after scripts/test.sh or
# scripts/main.sh has built the project). About 6 minutes on two cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
tb="$root/build/tissuebench"
out="${1:-$root/results/leg_skin_study}"
mkdir -p "$out"
data="$root/msd/data"
skin_line() { printf '  skin: {youngs_modulus: %s, thickness: 1.55e-3}\n' "$1"; }
for scene in gravity hamstrings quadriceps wobble drop; do
  src="$data/scenes/$scene.yaml"
  sed "s|\.\./scripts/|$data/scripts/|" "$src" > "$out/${scene}_A.yaml"
  sed -e "s|\.\./scripts/|$data/scripts/|" \
      -e "s|passive: {density: 920, youngs_modulus: 15000|passive: {density: 920, youngs_modulus: 2990|" \
      -e "s|muscle: {density: 1040, youngs_modulus: 75000|muscle: {density: 1040, youngs_modulus: 14950|" \
      "$src" > "$out/${scene}_B.yaml"
  grep -q "youngs_modulus: 14950" "$out/${scene}_B.yaml" || { echo "leg_skin_study: $src: materials not as expected" >&2; exit 2; }
  for v in C D; do
    e=$([ "$v" = C ] && echo 129e3 || echo 0.42e6)
    awk -v line="$(skin_line "$e")" '{print} /^  muscle: \{density: 1040, youngs_modulus: 14950/ {print line}' \
      "$out/${scene}_B.yaml" > "$out/${scene}_$v.yaml"
  done
done
ls "$out"/*_[ABCD].yaml | xargs -P "$(nproc)" -I{} bash -c \
  'n=$(basename {} .yaml); "$0" leg {} --out "$1/out_$n" --obj-every 0 > "$1/log_$n.txt" 2>&1 || true' "$tb" "$out"
python3 - "$out" <<'PY'
import json, os, sys
out = sys.argv[1]
keys = {
    "gravity": ["thigh_flesh_sag_end_m"],
    "hamstrings": ["knee_angle_max_deg", "back_muscle_volume_ratio_min"],
    "quadriceps": ["knee_angle_min_deg", "front_muscle_volume_ratio_min"],
    "wobble": ["wobble_frequency_hz", "wobble_damping_ratio"],
    "drop": ["drop_swing_period_s", "drop_first_swing_peak_deg", "drop_damping_ratio", "drop_oscillations", "drop_rest_angle_deg"],
}
for scene, ks in keys.items():
    for v in "ABCD":
        d = os.path.join(out, f"out_{scene}_{v}")
        runs = [os.path.join(d, r) for r in sorted(os.listdir(d))] if os.path.isdir(d) else []
        runs = [r for r in runs if os.path.isfile(os.path.join(r, "summary.json"))] or ([d] if os.path.isfile(os.path.join(d, "summary.json")) else [])
        for r in runs:
            s = json.load(open(os.path.join(r, "summary.json")))
            m = s.get("values", {})
            vals = ", ".join(f"{k} {m.get(k, 'n/a')}" for k in ks)
            status = s.get("status", "?")
            extra = f" ({s.get('failure', '')})" if status != "complete" else ""
            wall = s.get("wall_per_simulated_second", float("nan"))
            print(f"{scene} {v} {os.path.basename(r) if r != d else ''}: {status}{extra} at {s.get('simulated_seconds', 0):.2f} s; {vals}; {wall:.2f} wall s per simulated s")
PY
