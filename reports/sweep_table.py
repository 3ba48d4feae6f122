#!/usr/bin/python3
"""Markdown tables from a sweep (tissuebench sweep ... -> NAME_sweep.json):
the Pareto front, the time error apart from the model error, and what each
optional part of the model costs and buys ("model only what a scene requires").

Usage: /usr/bin/python3 reports/sweep_table.py SWEEP.json
Standard library only.
"""
import json
import statistics
import sys


def pct(v):
    return "-" if v is None else "%.2f" % (100 * v)


def err(p):
    return p["load_rel_rms_working"] if p["load_rel_rms_working"] is not None else p["load_rel_rms"]


def main(path):
    s = json.load(open(path))
    pts = s["points"]
    ok = [p for p in pts if p["status"] == "complete"]
    print("### Sweep of `%s` (%d points, %d stable; FEM %s RMS %.4g)\n"
          % (s["spec"], len(pts), len(ok), s["load_series"], s["load_rms_fem"]))
    print("FEM reference: %s, %d dofs, cost %.3g wall s per simulated s.\n"
          % (s["fem"]["label"], s["fem"]["dofs"], s["fem"]["cost"]))
    if s.get("fem_levels"):
        print("**The FEM's own trade** (other degree / refinement levels on the same coarse cells; error: "
              "load curve against the reference's):\n")
        print("| FEM | dofs | cost | error vs reference % |")
        print("|---|---:|---:|---:|")
        print("| %s (reference) | %d | %.3g | 0 |" % (s["fem"]["label"], s["fem"]["dofs"], s["fem"]["cost"]))
        for lv in s["fem_levels"]:
            print("| Q%d, refinement %d (%s) | %d | %.3g | %s |" % (lv["degree"], lv["refinement"], lv["label"],
                                                                  lv["dofs"], lv["cost"], pct(lv["load_rel_rms"])))
        print()

    print("**Pareto front** (cost = wall s per simulated s; error = relative RMS of the load curve "
          "over the working range):\n")
    print("| h / mm | dt / ms | integrator | terms | threshold | tets | cost | +memory / MB | error % |")
    print("|---:|---:|---|---|---|---:|---:|---:|---:|")
    for p in sorted((p for p in ok if p["pareto"]), key=lambda p: p["cost"]):
        print("| %.2f | %s | %s | %s | %s | %d | %.3g | %.1f | %s |" % (
            1e3 * p["spacing"], "adaptive" if p["dt"] is None else "%.3g" % (1e3 * p["dt"]), p["integrator"],
            p["terms"], "off" if not p["threshold"] else "%.2g" % p["threshold"], p["tets"], p["cost"],
            p["model_rss_mb"] or 0.0, pct(err(p))))

    print("\n**Time error apart from model error** (terms all, threshold off; time error: against the CVODE "
          "run of the same spatial model; model error: the CVODE run against the FEM):\n")
    print("| h / mm | integrator | dt / ms | status | cost | time error % | model error % | total error % |")
    print("|---:|---|---:|---|---:|---:|---:|---:|")
    for p in pts:
        if p["terms"] != "all" or p["threshold"]:
            continue
        cv = [q for q in ok if q["integrator"] == "cvode" and q["spacing"] == p["spacing"] and q["terms"] == "all"
              and not q["threshold"]]
        model = pct(err(cv[0])) if cv else "-"
        print("| %.2f | %s | %s | %s | %s | %s | %s | %s |" % (
            1e3 * p["spacing"], p["integrator"], "adaptive" if p["dt"] is None else "%.3g" % (1e3 * p["dt"]),
            "ok" if p["status"] == "complete" else ("timeout" if p["status"] == "timeout" else "unstable (t = %.3g s)" % (p["failure_time"] or 0)),
            "-" if p["cost"] is None else "%.3g" % p["cost"], pct(p["time_error"]), model,
            pct(err(p)) if p["status"] == "complete" else "-"))

    print("\n**Model only what a scene requires** (pairs of points equal in every other knob; cost ratio = "
          "with / without; medians over the pairs where both ran):\n")
    print("| part | pairs | both stable | without: unstable | cost ratio | error with % | error without % | "
          "volume error with | volume error without |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")

    def key(p, *skip):
        return tuple(p[k] for k in ("spacing", "dt", "integrator", "terms", "threshold") if k not in skip)

    def pairs(with_pred, without_pred, skip):
        w = {key(p, skip): p for p in pts if with_pred(p)}
        o = {key(p, skip): p for p in pts if without_pred(p)}
        return [(w[k], o[k]) for k in w if k in o]

    parts = [
        ("face repulsion", lambda p: p["terms"] == "all", lambda p: p["terms"] == "no_repulsion", "terms"),
        ("volume preservation", lambda p: p["terms"] == "all", lambda p: p["terms"] == "no_volume", "terms"),
        ("repulsion + volume", lambda p: p["terms"] == "all", lambda p: p["terms"] == "springs_dampers", "terms"),
        ("0.7 threshold (on vs off; terms all)", lambda p: p["terms"] == "all" and p["threshold"],
         lambda p: p["terms"] == "all" and not p["threshold"], "threshold"),
    ]
    for name, wp, op, skip in parts:
        pr = pairs(wp, op, skip)
        both = [(a, b) for a, b in pr if a["status"] == "complete" and b["status"] == "complete"]
        unstable_without = sum(1 for a, b in pr if a["status"] == "complete" and b["status"] != "complete")
        if not both:
            print("| %s | %d | 0 | %d | - | - | - | - | - |" % (name, len(pr), unstable_without))
            continue
        ratio = statistics.median(a["cost"] / b["cost"] for a, b in both)
        ew = statistics.median(err(a) for a, b in both)
        eo = statistics.median(err(b) for a, b in both)
        vw = [a["volume_ratio_max_error"] for a, b in both if a["volume_ratio_max_error"] is not None]
        vo = [b["volume_ratio_max_error"] for a, b in both if b["volume_ratio_max_error"] is not None]
        print("| %s | %d | %d | %d | %.2f | %s | %s | %s | %s |" % (
            name, len(pr), len(both), unstable_without, ratio, pct(ew), pct(eo),
            "%.3f" % statistics.median(vw) if vw else "-", "%.3f" % statistics.median(vo) if vo else "-"))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
