#!/usr/bin/python3
"""The accuracy report of a suite run: DIR/report/index.html (self-contained:
every figure embedded as a PNG data URI) and DIR/report/summary.md.

Usage: /usr/bin/python3 reports/make_report.py DIR      (DIR: `tissuebench suite --out DIR`)

Reads DIR/suite.json (the manifest) and the files it lists: the HDF5 results
of the FEM reference and the MSD variants of each benchmark, their comparison
JSONs, the sweep, stability, verification and convergence outputs (layouts in
benchmarks/RESULTS.md), and the leg scenes under its "leg" key (reports/leg_report.py:
curves, a filmstrip checked not blank, the thesis' outcomes beside the measured
ones). Needs Debian's python3-matplotlib, python3-h5py and python3-jinja2
(scripts/setup.sh installs them).
"""
import base64
import html
import io
import json
import os
import platform
import sys

import h5py
import jinja2
import matplotlib
import yaml

import leg_report
import pareto_chart

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The x axis and its label per loading; the y axis comes from the comparison
# (its load_series and units).
X_AXIS = {
    "uniaxial": ("strain", "nominal strain ε (1)"),
    "simple_shear": ("shear_strain", "shear strain γ (1)"),
    "static": ("load_factor", "load factor (1)"),
    "vibration": ("time", "time t (s)"),
    "indentation": ("depth", "indenter depth d (m)"),
}
Y_LABEL = {
    "nominal_stress": "nominal stress (Pa)",
    "shear_stress": "shear stress σxz (Pa)",
    "tip_displacement_x": "tip displacement x (m)",
    "tip_displacement_y": "tip displacement y (m)",
    "tip_displacement_z": "tip displacement z (m)",
    "tip_displacement": "tip displacement (m)",
    "indentation_force": "indentation force (N)",
}
VARIANT_STYLE = {"thesis": ("tab:red", "--"), "physical": ("tab:blue", "-"), "calibrated": ("tab:green", "-"),
                 "lattice": ("tab:orange", "-"), "continuum": ("tab:purple", "-."),
                 "physical_lattice": ("tab:brown", "-"), "neo_lattice": ("tab:olive", "-")}


def closed_form(fem_path, loading):
    """A closed form the benchmark can be held against, where one exists:
    (label, function of the x axis) for the load curve, or a note."""
    with h5py.File(fem_path, "r") as f:
        spec = yaml.safe_load(f["meta"].attrs["spec"])
        mat = {k: float(v) for k, v in f["meta"]["material"].attrs.items()}
    geo, load = spec.get("geometry", {}), spec.get("loading", {})
    E, rho = mat.get("youngs_modulus"), mat.get("density")
    if loading == "static" and geo.get("shape") == "box" and load.get("fixed", "bottom") == "left":
        L, b, h = geo["size"]
        inertia = b * h ** 3 / 12.0
        trac = load.get("traction")
        if trac and trac.get("face") == "right":
            F = trac["force"][2]
            return ("beam theory F L³/3EI (small deflection)", lambda lam: lam * F * L ** 3 / (3 * E * inertia)), None
        g = (load.get("gravity") or [0, 0, 0])[2]
        if g:
            w = rho * g * b * h
            return ("beam theory w L⁴/8EI (small deflection)", lambda lam: lam * w * L ** 4 / (8 * E * inertia)), None
    if loading == "vibration" and geo.get("shape") == "box":
        f1 = (E / rho) ** 0.5 / (4 * geo["size"][2])
        return None, "closed form for a slender fixed–free bar, √(E/ρ)/4L: %.4g Hz" % f1
    return None, None


def series(path):
    with h5py.File(path, "r") as f:
        return {k: f["series"][k][()] for k in f["series"].keys()}


def png(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def pct(v, digits=3):
    return "–" if v is None else ("%." + str(digits) + "g %%") % (100 * v)


def num(v, digits=4):
    return "–" if v is None else ("%." + str(digits) + "g") % v


def load(path):
    with open(path) as f:
        return json.load(f)


def benchmark_section(d, b):
    """Figures and the error table of one benchmark."""
    fem = series(os.path.join(d, b["fem_file"]))
    runs, rows = [], []
    for v in b["variants"]:
        cmp = load(os.path.join(d, v["compare_file"])) if v.get("compare_file") else None
        msd = series(os.path.join(d, v["msd_file"])) if os.path.exists(os.path.join(d, v["msd_file"])) else None
        runs.append((v, msd, cmp))
        rows.append({
            "variant": v["variant"], "status": v["status"], "failure": v["failure"],
            "load": pct(cmp and cmp["load_rel_rms"]), "working": pct(cmp and cmp["load_rel_rms_working"]),
            "volume": num(cmp and cmp["volume_ratio_max_error"], 3),
            "disp": pct(cmp and cmp["displacement_rel_rms"]), "freq": pct(cmp and cmp["frequency_rel_error"]),
            "zeta": num(cmp and cmp["damping_ratio_abs_error"], 3),
            "cost": num(cmp and cmp["msd_cost"], 3), "ratio": num(cmp and cmp["cost_ratio"], 3),
            "error_value": cmp and (cmp["load_rel_rms_working"] if cmp["load_rel_rms_working"] is not None
                                    else cmp["load_rel_rms"]),
            "ratio_value": cmp and cmp["cost_ratio"],
        })
    cmp0 = next((c for _, _, c in runs if c), None)
    ykey = cmp0["load_series"] if cmp0 else None
    xkey, xlabel = X_AXIS.get(b["loading"], ("time", "time t (s)"))
    curve, note = closed_form(os.path.join(d, b["fem_file"]), b["loading"])
    if curve:
        note = "dotted: " + curve[0] + ", valid only while the deflection is small against the length"
    figures = []
    if ykey:
        fig, ax = plt.subplots(figsize=(6.4, 4.0))
        ax.plot(fem[xkey], fem[ykey], "k-", lw=2.2, label="FEM reference")
        if curve:
            xs = fem[xkey]
            ax.plot(xs, [curve[1](x) for x in xs], color="0.5", ls=":", lw=1.5, label=curve[0])
        for v, msd, _ in runs:
            if msd is None or ykey not in msd:
                continue
            colour, style = VARIANT_STYLE.get(v["variant"], ("tab:gray", ":"))
            label = "MSD, %s%s" % (v["variant"], "" if v["status"] == "complete" else " (blew up)")
            ax.plot(msd[xkey], msd[ykey], color=colour, ls=style, lw=1.3, label=label)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(Y_LABEL.get(ykey, ykey))
        ax.set_title("%s: %s" % (b["name"], Y_LABEL.get(ykey, ykey).split(" (")[0]))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        figures.append(("load curve", png(fig)))
    if "volume_ratio" in fem and b["loading"] in ("uniaxial", "simple_shear", "indentation"):
        fig, ax = plt.subplots(figsize=(6.4, 3.2))
        ax.plot(fem[xkey], fem["volume_ratio"], "k-", lw=2.2, label="FEM reference")
        for v, msd, _ in runs:
            if msd is None or "volume_ratio" not in msd:
                continue
            colour, style = VARIANT_STYLE.get(v["variant"], ("tab:gray", ":"))
            ax.plot(msd[xkey], msd["volume_ratio"], color=colour, ls=style, lw=1.3, label="MSD, " + v["variant"])
        ax.set_xlabel(xlabel)
        ax.set_ylabel("volume ratio V/V₀ (1)")
        ax.set_title("%s: volume" % b["name"])
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        figures.append(("volume", png(fig)))
    return {"name": b["name"], "description": b["description"], "loading": b["loading"], "spec": b["spec"],
            "sha": b["spec_sha256"][:16], "rows": rows, "figures": figures,
            "units": cmp0["units"] if cmp0 else "", "load_series": ykey or "–", "closed_form": note,
            "fem_frequency": num(cmp0 and cmp0["frequency_fem"], 4)}


LADDER_MARKERS = "osD^vP*X"


def ladder_section(benches, variants):
    """The model ladder: every variant's cost ratio MSD/FEM against its load-curve
    error (working range where the benchmark has one), one marker per benchmark,
    one colour per variant, and the same figures as a table."""
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for v in variants:
        colour, _ = VARIANT_STYLE.get(v, ("tab:gray", ":"))
        for k, b in enumerate(benches):
            r = next((r for r in b["rows"] if r["variant"] == v), None)
            if not r or r["status"] != "complete" or not r["error_value"] or not r["ratio_value"]:
                continue
            ax.scatter([r["ratio_value"]], [100 * r["error_value"]], color=colour,
                       marker=LADDER_MARKERS[k % len(LADDER_MARKERS)], s=34, alpha=0.85)
    for v in variants:
        ax.scatter([], [], color=VARIANT_STYLE.get(v, ("tab:gray", ":"))[0], marker="o", label="MSD, " + v)
    for k, b in enumerate(benches):
        ax.scatter([], [], color="0.4", marker=LADDER_MARKERS[k % len(LADDER_MARKERS)], label=b["name"])
    ax.axvline(1.0, color="k", lw=1, ls="--", label="the FEM's own cost")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("cost ratio MSD / FEM (CPU s per simulated s)")
    ax.set_ylabel("load-curve error against the FEM (%)")
    ax.set_title("the model ladder: what each variant trades")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    rows = []
    for b in benches:
        cells = []
        for v in variants:
            r = next((r for r in b["rows"] if r["variant"] == v), None)
            if not r or r["status"] != "complete":
                cells.append("blew up" if r else "–")
            else:
                cells.append("%s at %s" % (pct(r["error_value"]), r["ratio"]))
        rows.append({"name": b["name"], "cells": cells})
    return {"figure": png(fig), "rows": rows}


def sweep_section(d, path):
    s = load(os.path.join(d, path))
    pts = [p for p in s["points"] if p["status"] == "complete"]

    err = pareto_chart.error
    fig = pareto_chart.sweep_figure(s)
    rows = [{
        "h": "%.2f" % (1e3 * p["spacing"]), "dt": "adaptive" if p["dt"] is None else "%.3g" % (1e3 * p["dt"]),
        "integrator": p["integrator"], "terms": p["terms"], "threshold": "off" if not p["threshold"] else "%.2g" % p["threshold"],
        "cost": num(p["cost"], 3), "err": pct(err(p)), "time": pct(p["time_error"]), "pareto": "★" if p["pareto"] else "",
    } for p in sorted(pts, key=lambda p: p["cost"])]
    unstable = [p for p in s["points"] if p["status"] != "complete"]
    fem_rows = [{"label": s["fem"]["label"] + " (reference)", "dofs": s["fem"]["dofs"], "cost": num(s["fem"]["cost"], 3),
                 "err": "0 (by definition)"}]
    fem_rows += [{"label": "%s, Q%d refinement %d" % (lv["label"], lv["degree"], lv["refinement"]), "dofs": lv["dofs"],
                  "cost": num(lv["cost"], 3), "err": pct(lv["load_rel_rms"])} for lv in s.get("fem_levels", [])]
    return {"spec": s["spec"], "figure": png(fig), "rows": rows, "unstable": len(unstable), "fem_rows": fem_rows,
            "load_series": s["load_series"]}


def main(d):
    m = load(os.path.join(d, "suite.json"))
    benches = [benchmark_section(d, b) for b in m.get("benchmarks", [])]
    sweeps = [sweep_section(d, p) for p in m.get("sweeps", [])]
    ladder = ladder_section(benches, m.get("variants", [])) if benches else None
    try:
        legs = leg_report.leg_section(d, m)
    except leg_report.LegRenderError as e:
        sys.exit("report: the leg's filmstrip failed its check: %s" % e)
    stability = []
    for p in m.get("stability", []):
        s = load(os.path.join(d, p))
        stability.append({"spec": s["spec"], "dt": s["dt_search"], "extremes": [{
            "case": e["case"], "description": e["description"], "terms": e["terms"], "dt": num(e["dt"], 3),
            "integrator": e.get("integrator", "-"),
            "finite": "yes" if e["finite"] else "NO", "failure_time": num(e["failure_time"], 3),
            "inverted": e["max_inverted"], "volume": num(e["volume_error"], 3)} for e in s["extremes"]]})
    convergence = [load(os.path.join(d, p)) for p in m.get("convergence", [])]
    prov = dict(m.get("provenance", {}))
    prov.update({"python": platform.python_version(), "matplotlib": matplotlib.__version__,
                 "h5py": h5py.__version__, "jinja2": jinja2.__version__})
    ctx = {"m": m, "prov": prov, "benches": benches, "sweeps": sweeps, "ladder": ladder, "stability": stability,
           "verification": m.get("verification", []), "convergence": convergence, "pct": pct, "num": num,
           "legs": legs, "leg_sources": leg_report.pendulum_sources() if any(s["published"] for s in legs) else []}
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(os.path.dirname(os.path.abspath(__file__))),
                             autoescape=jinja2.select_autoescape(["html"]))
    out = os.path.join(d, "report")
    os.makedirs(out, exist_ok=True)
    for name, template in (("index.html", "report.html.j2"), ("summary.md", "summary.md.j2")):
        text = env.get_template(template).render(**ctx)
        tmp = os.path.join(out, name + ".tmp")
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, os.path.join(out, name))
    print("report: %s (and %s)" % (os.path.join(out, "index.html"), os.path.join(out, "summary.md")))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
