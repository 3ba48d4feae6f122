#!/usr/bin/python3
"""Pictures of a meshed limb: the geometric surfaces and the physical layer.

    /usr/bin/python3 reports/render_leg.py MESH_DIR OUT.png [--surfaces LEG_DIR]

MESH_DIR is the output of `tissuebench mesh` (mesh.vtu, bone_points.vtu,
tendons.vtu); LEG_DIR holds the OBJ surfaces (default: the scene's folder is
not known here, so msd/data/leg). Three panels from the side (x forward, z up):
the surfaces (skin translucent, bones, muscles), the tet mesh's boundary faces
coloured by region, and the internal regions with bone points and tendon
strands. Uses Debian's python3-matplotlib and numpy only.
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ET

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402,F401
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

REGION_COLOURS = {0: "#e8b796", 1: "#c0392b", 2: "#8e44ad", 3: "#ecf0f1", 4: "#bdc3c7"}
REGION_NAMES = {0: "passive tissue", 1: "front muscle", 2: "back muscle", 3: "upper bone", 4: "lower bone"}


def read_obj(path):
    """An OBJ file's vertices (V x 3) and triangles (T x 3, 0-based; polygons
    fan-triangulated). Also used by leg_report.py."""
    vs, fs = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vs.append([float(t) for t in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(t.split("/")[0]) - 1 for t in line.split()[1:]]
                for k in range(1, len(idx) - 1):   # fan-triangulate polygons
                    fs.append([idx[0], idx[k], idx[k + 1]])
    return np.array(vs, dtype=float), np.array(fs, dtype=np.int64)


def read_vtu(path):
    root = ET.parse(path).getroot()
    piece = root.find(".//Piece")

    def array(parent, name):
        for a in parent.iter("DataArray"):
            if a.get("Name") == name:
                return np.array(a.text.split(), dtype=float)
        return None

    text = piece.find("Points").find("DataArray").text or ""
    pts = np.array(text.split(), dtype=float).reshape(-1, 3)
    cells = piece.find("Cells")
    conn = array(cells, "connectivity")
    offsets = array(cells, "offsets")
    if conn is None or len(offsets) == 0:
        return pts, [], {}
    conn, offsets = conn.astype(int), offsets.astype(int)
    cell_data = {}
    cd = piece.find("CellData")
    if cd is not None:
        for a in cd.iter("DataArray"):
            cell_data[a.get("Name")] = np.array(a.text.split(), dtype=float)
    starts = np.concatenate([[0], offsets[:-1]])
    return pts, [conn[s:e] for s, e in zip(starts, offsets)], cell_data


def boundary_faces(tets, region):
    """Faces used by one tet only, with that tet's region."""
    seen = {}
    for t, r in zip(tets, region):
        for f in ((t[0], t[1], t[2]), (t[0], t[1], t[3]), (t[0], t[2], t[3]), (t[1], t[2], t[3])):
            key = tuple(sorted(f))
            if key in seen:
                seen[key] = None
            else:
                seen[key] = (f, r)
    return [v for v in seen.values() if v is not None]


def region_faces(tets, region, keep):
    """Boundary faces of the tets whose region is in `keep`."""
    sel = [(t, r) for t, r in zip(tets, region) if r in keep]
    return boundary_faces([t for t, _ in sel], [r for _, r in sel])


def setup(ax, lo, hi, title):
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(hi - lo))  # true proportions
    ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(3))
    ax.yaxis.set_major_locator(matplotlib.ticker.MaxNLocator(2))
    ax.view_init(elev=8, azim=-62)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.set_title(title, fontsize=10)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mesh_dir")
    ap.add_argument("out")
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--surfaces", default=os.path.join(here, "..", "msd", "data", "leg"))
    a = ap.parse_args()

    pts, tets, cd = read_vtu(os.path.join(a.mesh_dir, "mesh.vtu"))
    region = cd["region"].astype(int)
    lo, hi = pts.min(axis=0) - 0.02, pts.max(axis=0) + 0.02
    fig = plt.figure(figsize=(13, 9))

    ax = fig.add_subplot(1, 3, 1, projection="3d")
    for name, colour, alpha in (("skin", "#e8b796", 0.18), ("upper_bone", "#dddddd", 1.0),
                                ("lower_bone", "#bbbbbb", 1.0), ("front_muscle", "#c0392b", 0.9),
                                ("back_muscle", "#8e44ad", 0.9)):
        path = os.path.join(a.surfaces, name + ".obj")
        if not os.path.exists(path):
            continue
        v, f = read_obj(path)
        ax.add_collection3d(Poly3DCollection(v[f], facecolor=colour, edgecolor="none", alpha=alpha))
    setup(ax, lo, hi, "geometric layer: surfaces")

    ax = fig.add_subplot(1, 3, 2, projection="3d")
    faces = boundary_faces(tets, region)
    polys = np.array([pts[list(f)] for f, _ in faces])
    ax.add_collection3d(Poly3DCollection(polys, facecolor=[REGION_COLOURS[r] for _, r in faces],
                                         edgecolor="#555555", linewidths=0.2))
    setup(ax, lo, hi, f"physical layer: {len(tets)} tets")

    ax = fig.add_subplot(1, 3, 3, projection="3d")
    faces = region_faces(tets, region, {1, 2, 3, 4})
    polys = np.array([pts[list(f)] for f, _ in faces])
    ax.add_collection3d(Poly3DCollection(polys, facecolor=[REGION_COLOURS[r] for _, r in faces],
                                         edgecolor="#333333", linewidths=0.2, alpha=0.8))
    bp_path = os.path.join(a.mesh_dir, "bone_points.vtu")
    if os.path.exists(bp_path):
        bpts, _, _ = read_vtu(bp_path)
        if len(bpts):
            ax.scatter(bpts[:, 0], bpts[:, 1], bpts[:, 2], color="black", s=12, label="bone points")
    td_path = os.path.join(a.mesh_dir, "tendons.vtu")
    if os.path.exists(td_path):
        tpts, strands, _ = read_vtu(td_path)
        for s in strands:
            ax.plot(tpts[s, 0], tpts[s, 1], tpts[s, 2], color="#1f77b4", linewidth=1.2)
    for r in (1, 2, 3, 4):
        ax.plot([], [], color=REGION_COLOURS[r], linewidth=6, label=REGION_NAMES[r])
    ax.plot([], [], color="#1f77b4", label="tendon strands")
    ax.legend(loc="upper right", fontsize=7)
    setup(ax, lo, hi, "internal regions, bone points, tendons")

    fig.tight_layout()
    fig.savefig(a.out, dpi=90, bbox_inches="tight")
    print(f"written: {a.out}")


if __name__ == "__main__":
    sys.exit(main())
