#!/usr/bin/python3
"""The thesis' tuned leg scenes beside the physiological leg's: the knee angle
over time of each scene, both runs in one panel (docs/leg-motion.md, "The
physiological leg").

  /usr/bin/python3 reports/leg_side_by_side.py TUNED_DIR PHYSIOLOGICAL_DIR OUT.png

Each DIR holds one folder per scene as `tissuebench leg SCENE.yaml --out
DIR/SCENE` writes it (DIR/SCENE/leg.csv; a scene with variants: its first
variant's folder, in the order of DIR/SCENE/summary.json). A scene missing from a folder, or a run that failed
(summary.json status other than complete), is drawn as far as its leg.csv goes
and marked in the legend. Debian's python3-matplotlib; no pip.
"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SCENES = ["gravity", "pretension", "external_object", "hamstrings", "quadriceps", "co_contraction", "obstacle", "drop",
          "swing", "wobble"]


def read_json(path):
    with open(path) as f:
        return json.load(f)


def run_folder(root, scene):
    """The scene's run folder; for a scene with variants, its first variant's
    (the order of the index DIR/SCENE/summary.json, which is the scene's)."""
    d = os.path.join(root, scene)
    if os.path.isfile(os.path.join(d, "leg.csv")):
        return d
    index = os.path.join(d, "summary.json")
    if os.path.isfile(index):
        for v in read_json(index).get("variants", {}):
            if os.path.isfile(os.path.join(d, v, "leg.csv")):
                return os.path.join(d, v)
    return None


def knee_curve(root, scene):
    """(times, knee angles in degrees, status) or None."""
    d = run_folder(root, scene)
    if d is None:
        return None
    t, a = [], []
    with open(os.path.join(d, "leg.csv")) as f:
        for row in csv.DictReader(f):
            t.append(float(row["time"]))
            a.append(float(row["knee_angle"]))
    status = "?"
    if os.path.isfile(os.path.join(d, "summary.json")):
        s = read_json(os.path.join(d, "summary.json"))
        status = s.get("status", "?")
        if status != "complete":
            status = "failed at %.2f s" % s.get("simulated_seconds", t[-1] if t else 0.0)
    return t, a, status


def main(argv):
    if len(argv) != 4:
        sys.stderr.write(__doc__)
        return 2
    tuned, phys, out = argv[1:]
    fig, axes = plt.subplots(5, 2, figsize=(10, 13), sharex=False)
    for ax, scene in zip(axes.flat, SCENES):
        for root, label, style in ((tuned, "thesis' tuned constants", "-"), (phys, "physiological", "--")):
            c = knee_curve(root, scene)
            if c is None:
                ax.plot([], [], style, label=label + " (no run)")
                continue
            t, a, status = c
            ax.plot(t, a, style, lw=1.2, label=label + ("" if status == "complete" else " (" + status + ")"))
        ax.set_title(scene, fontsize=10)
        ax.set_ylabel("knee flexion (°)", fontsize=8)
        ax.set_xlabel("time (s)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print("written:", out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
