#!/usr/bin/python3
"""Markdown tables from tissuebench stability (NAME_stability.json): the largest
stable time step per integrator and term set, and the extreme loads.

Usage: /usr/bin/python3 reports/stability_table.py NAME_stability.json
"""
import json
import sys


def g(v, fmt="%.3g"):
    return "-" if v is None else fmt % v


def main(path):
    s = json.load(open(path))
    if s["dt_search"]:
        print("| integrator | terms | largest stable dt / s | smallest unstable dt / s | trials | detector that fired |")
        print("|---|---|---:|---:|---:|---|")
        for d in s["dt_search"]:
            print("| %s | %s | %s | %s | %d | %s |" % (d["integrator"], d["terms"], g(d["largest_stable_dt"]),
                                                    g(d["smallest_unstable_dt"]), d["trials"],
                                                    d["reason"].split(" at t =")[0][:70]))
    if s["extremes"]:
        print("\n| case | integrator | terms | dt / s | finite | failed at t / s | inverted max / end | "
              "max \\|V/V0 − 1\\| | load range / Pa | failure |")
        print("|---|---|---|---:|---|---:|---:|---:|---|---|")
        for r in s["extremes"]:
            print("| %s | %s | %s | %s | %s | %s | %d / %d | %.3f | %s … %s | %s |" % (
                r["case"], r.get("integrator", "-"), r["terms"], g(r["dt"]), "yes" if r["finite"] else "**no**", g(r["failure_time"]),
                r["max_inverted"], r["final_inverted"], r["volume_error"], g(r["min_load"], "%.3g"),
                g(r["max_load"], "%.3g"), r["failure"].split(" (")[0].split(" at t =")[0][:60]))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
