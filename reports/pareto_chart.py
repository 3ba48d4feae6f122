#!/usr/bin/python3
"""The speed-accuracy chart of a sweep (tissuebench sweep ... -> NAME_sweep.json),
both families on one set of axes: every MSD point by its rung (the force-term
set: thesis element, continuum element, neo-Hookean lattice, ...) over mesh
spacing h and time step dt, and the FEM over degree and refinement (its levels
against its reference). The MSD Pareto front is drawn as a line and its points
are labelled with their h and dt, so a reader sees which resolution buys which
error. The report (make_report.py) draws each sweep of a suite with it;
benchmarks/README.md shows the charts of the recorded sweeps.

Usage: /usr/bin/python3 reports/pareto_chart.py SWEEP.json OUT.png [--title TEXT]
Needs Debian's python3-matplotlib (scripts/setup.sh installs it).

Axes: cost = wall s per simulated s of the run (the same clock for both
families, measured in the same sweep); error = relative RMS of the load curve
against the FEM reference over the working range where the spec has one. The
reference itself has error 0 by definition and cannot sit on a log axis: it is
the vertical line at its cost.
"""
import json
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# One marker per rung of the MSD model ladder (sweep term sets).
TERM_MARKERS = (("all", "o", "thesis element (all terms)"), ("springs_dampers", "s", "springs + dampers"),
                ("no_repulsion", "^", "no repulsion"), ("no_volume", "v", "no volume term"),
                ("continuum", "P", "continuum element"), ("neo_lattice", "*", "neo-Hookean lattice"))
# One colour per integrator family (dt is in the labels).
INTEGRATOR_COLOURS = {"symplectic_euler": "tab:blue", "velocity_verlet": "tab:orange", "explicit_euler": "tab:gray",
                      "backward_euler": "tab:brown", "bdf2": "tab:red", "quasi_static": "tab:green",
                      "cvode": "k"}


def error(p):
    """A point's error: over the working range where the spec has one."""
    return p["load_rel_rms_working"] if p.get("load_rel_rms_working") is not None else p["load_rel_rms"]


def point_label(p):
    dt = "adaptive" if p["dt"] is None else "%.3g ms" % (1e3 * p["dt"])
    return "h %.3g mm, %s" % (1e3 * p["spacing"], dt if p["integrator"] != "quasi_static" else "static")


def sweep_figure(s, title=None):
    """The chart of sweep JSON `s` (dict) as a matplotlib figure."""
    pts = [p for p in s["points"] if p["status"] == "complete" and p["cost"] is not None and error(p) is not None]
    fig, ax = plt.subplots(figsize=(7.2, 4.6))
    for terms, marker, name in TERM_MARKERS:
        sel = [p for p in pts if p["terms"] == terms]
        if not sel:
            continue
        ax.scatter([p["cost"] for p in sel], [100 * error(p) for p in sel], marker=marker, s=46 if marker == "*" else 28,
                   c=[INTEGRATOR_COLOURS.get(p["integrator"], "tab:gray") for p in sel], alpha=0.85,
                   edgecolors="none")
        ax.scatter([], [], marker=marker, color="0.35", label="MSD, " + name)
    for integ in sorted({p["integrator"] for p in pts}):
        ax.scatter([], [], marker="o", color=INTEGRATOR_COLOURS.get(integ, "tab:gray"), s=14,
                   label="  " + integ.replace("_", " "))
    front = sorted((p for p in pts if p.get("pareto")), key=lambda p: p["cost"])
    if front:
        ax.plot([p["cost"] for p in front], [100 * error(p) for p in front], "k--", lw=0.9, label="MSD Pareto front")
        for p in front:
            ax.annotate(point_label(p), (p["cost"], 100 * error(p)), textcoords="offset points", xytext=(4, 3),
                        fontsize=6, color="0.25")
    ax.axvline(s["fem"]["cost"], color="tab:purple", lw=1.4, label="FEM reference cost (%s)" % s["fem"]["label"])
    levels = [lv for lv in s.get("fem_levels", []) if lv.get("load_rel_rms") and lv["load_rel_rms"] > 0]
    if levels:
        levels.sort(key=lambda lv: lv["cost"])
        ax.plot([lv["cost"] for lv in levels], [100 * lv["load_rel_rms"] for lv in levels], "D-", color="tab:purple",
                lw=0.9, ms=6, label="FEM levels vs reference")
        for lv in levels:
            ax.annotate("Q%d r%d, %d dofs" % (lv["degree"], lv["refinement"], lv["dofs"]),
                        (lv["cost"], 100 * lv["load_rel_rms"]), textcoords="offset points", xytext=(4, -9),
                        fontsize=6, color="tab:purple")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("cost (wall s per simulated s)")
    ax.set_ylabel("load-curve error against the FEM reference (%)")
    ax.set_title(textwrap.fill(title or "speed–accuracy: %s" % s["spec"], 60), fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.tight_layout()
    return fig


def main(argv):
    if len(argv) not in (3, 5) or (len(argv) == 5 and argv[3] != "--title"):
        sys.stderr.write("usage: pareto_chart.py SWEEP.json OUT.png [--title TEXT]\n")
        return 2
    try:
        with open(argv[1]) as f:
            s = json.load(f)
    except (OSError, ValueError) as e:
        sys.stderr.write("pareto_chart.py: %s: %s\n" % (argv[1], e))
        return 2
    if "points" not in s or "fem" not in s:
        sys.stderr.write("pareto_chart.py: %s is not a sweep JSON (no 'points' or 'fem')\n" % argv[1])
        return 2
    fig = sweep_figure(s, argv[4] if len(argv) == 5 else None)
    fig.savefig(argv[2], dpi=110)
    print("chart: %s" % argv[2])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
