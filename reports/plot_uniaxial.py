#!/usr/bin/python3
"""Plot uni-axial results files: nominal stress and volume ratio against nominal
strain (the thesis' figures 5.5, 5.11 and 5.15), one column per file.

Usage: /usr/bin/python3 reports/plot_uniaxial.py OUT.png FILE.h5 [FILE.h5 ...]
Needs Debian's python3-matplotlib and python3-h5py.
"""
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with h5py.File(path, "r") as f:
        meta = dict(f["meta"].attrs)
        series = {k: f["series"][k][()] for k in f["series"]}
    return meta, series


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    out, files = argv[1], argv[2:]
    fig, axes = plt.subplots(2, len(files), figsize=(4.2 * len(files), 6.4), squeeze=False)
    for col, path in enumerate(files):
        meta, s = read(path)
        name = meta.get("spec_name", path)
        status = meta.get("status", "?")
        ax = axes[0][col]
        ax.plot(s["strain"], s["nominal_stress"], lw=1.0)
        ax.set_title(f"{name}\n({status})", fontsize=9)
        ax.set_xlabel("nominal strain")
        ax.set_ylabel("nominal stress [Pa]")
        ax.axhline(0, color="0.7", lw=0.5)
        ax.grid(alpha=0.3)
        ax2 = axes[1][col]
        ax2.plot(s["strain"], 100 * s["volume_ratio"], lw=1.0, color="C1")
        ax2.set_xlabel("nominal strain")
        ax2.set_ylabel("volume [% of rest]")
        ax2.grid(alpha=0.3)
        if "inverted_elements" in s and s["inverted_elements"].max() > 0:
            ax3 = ax2.twinx()
            ax3.plot(s["strain"], s["inverted_elements"], lw=0.8, color="C3", alpha=0.6)
            ax3.set_ylabel("inverted tets", color="C3")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
