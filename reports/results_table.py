#!/usr/bin/python3
"""Print a Markdown table of runs from results files: spec, solver, status,
mesh, Newton iterations, linear-solver and wall time, and the last value of
chosen series.

Usage: /usr/bin/python3 reports/results_table.py FILE.h5 [...] [--series NAME ...]
Needs Debian's python3-h5py.
"""
import sys

import h5py


def main(argv):
    files, series, i = [], [], 1
    while i < len(argv):
        if argv[i] == "--series":
            series.append(argv[i + 1])
            i += 2
        else:
            files.append(argv[i])
            i += 1
    if not files:
        print(__doc__)
        return 2
    head = ["spec", "solver", "status", "mesh", "Newton its", "factorisations", "linear solver s", "wall s"]
    head += [f"{s} (last)" for s in series]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for f in files:
        with h5py.File(f, "r") as h:
            m, t = dict(h["meta"].attrs), dict(h["timing"].attrs)
            row = [m.get("spec_name", f), m.get("solver", ""), m.get("status", ""), m.get("mesh_counts", ""),
                   "%d" % t.get("newton_iterations", 0), "%d" % t.get("factorizations", 0),
                   "%.2f" % t.get("linear_solver_seconds", 0.0), "%.2f" % t.get("wall_seconds", 0.0)]
            for s in series:
                row.append("%.6g" % h["series"][s][-1] if s in h["series"] else "")
        print("| " + " | ".join(str(c) for c in row) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
