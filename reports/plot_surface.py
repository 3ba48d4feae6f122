#!/usr/bin/python3
"""Render the deformed boundary surface stored in a results file's /fields at
chosen frames (a quick look without ParaView).

Usage: /usr/bin/python3 reports/plot_surface.py FILE.h5 OUT.png [TIME ...]
(default: the first and the last frame). Needs python3-h5py, python3-matplotlib.
"""
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    path, out = argv[1], argv[2]
    with h5py.File(path, "r") as h:
        f = h["fields"]
        X = f["surface_points"][()]
        T = f["surface_triangles"][()]
        times = f["surface_time"][()]
        U = f["surface_displacement"]
        wanted = [float(t) for t in argv[3:]] or [times[0], times[-1]]
        frames = [int(np.argmin(np.abs(times - t))) for t in wanted]
        name = h["meta"].attrs.get("spec_name", path)
        fig = plt.figure(figsize=(4.0 * len(frames), 4.6))
        lo = (X + np.min(U, axis=0)).min(axis=0)
        hi = (X + np.max(U, axis=0)).max(axis=0)
        for k, i in enumerate(frames):
            x = X + U[i]
            ax = fig.add_subplot(1, len(frames), k + 1, projection="3d")
            ax.plot_trisurf(x[:, 0], x[:, 1], x[:, 2], triangles=T, color="tan", edgecolor="0.3", linewidth=0.2)
            ax.set_xlim(lo[0], hi[0])
            ax.set_ylim(lo[1], hi[1])
            ax.set_zlim(lo[2], hi[2])
            ax.set_box_aspect(hi - lo)
            ax.set_title(f"{name}\nt = {times[i]:.2f} s", fontsize=9)
            ax.set_xlabel("x [m]")
            ax.set_ylabel("y [m]")
            ax.set_zlabel("z [m]")
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
