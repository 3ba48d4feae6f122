#!/usr/bin/python3
"""Markdown table of MSD-against-FEM errors per benchmark and calibration, from
the compare JSONs that benchmarks/calibration/compare_calibrations.sh writes
(OUT/<calibration>/<spec>_compare.json; keys: benchmarks/RESULTS.md).

Usage: /usr/bin/python3 reports/calibration_table.py OUT_DIR
"""
import json
import os
import sys

SPECS = ["uniaxial", "shear", "bending", "bending_gravity", "vibration", "indentation"]
ROLE = {"uniaxial": "target", "shear": "target", "bending": "held out", "bending_gravity": "held out",
        "vibration": "held out", "indentation": "held out"}


def pct(v):
    return "-" if v is None else "%.1f" % (100 * v)


def main(out):
    sets = ["uncalibrated"] + sorted(d for d in os.listdir(out) if d != "uncalibrated"
                                     and os.path.isdir(os.path.join(out, d)))
    print("| benchmark | role | constants | load error % | working range % | max volume error | "
          "displacement RMS % | frequency error % | damping ratio error |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|")
    for spec in SPECS:
        for s in sets:
            f = os.path.join(out, s, spec + "_compare.json")
            failure = os.path.join(out, s, spec + "_failure.txt")
            if os.path.exists(failure):
                print("| %s | %s | %s | %s |||||||" % (spec, ROLE[spec], s,
                                                     "**blew up**: " + open(failure).read().strip()[:160]))
                continue
            if not os.path.exists(f):
                continue
            c = json.load(open(f))
            print("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                spec, ROLE[spec], s, pct(c["load_rel_rms"]), pct(c["load_rel_rms_working"]),
                "-" if c["volume_ratio_max_error"] is None else "%.3f" % c["volume_ratio_max_error"],
                pct(c["displacement_rel_rms"]), pct(c["frequency_rel_error"]),
                "-" if c["damping_ratio_abs_error"] is None else "%+.3f" % c["damping_ratio_abs_error"]))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
