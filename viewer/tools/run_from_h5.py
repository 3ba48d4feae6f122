#!/usr/bin/python3
"""Development fixture generator: a leg run folder (leg.h5) -> the viewer's run data JSON.

The product is the C++ `tissuebench view` command; this script only makes
fixtures for the viewer's own development and browser tests. It writes the
format of viewer/README.md ("tissuebench-view/1"):

    /usr/bin/python3 viewer/tools/run_from_h5.py RUN_DIR OUT.json [--every N]
        [--max-frames N] [--plots a,b,c] [--no-frames] [--status S --failure TEXT]

RUN_DIR holds leg.h5 (/fields/skin_points, skin_triangles, skin_displacement,
skin_time and optionally bones_points, bones_triangles, bones_displacement;
/series/* with a "units" attribute; /meta attributes status, failure,
spec_name, variant). --every N keeps every N-th frame (and the same series
rows when the series has one row per frame). --no-frames writes a run with
zero frames (a run that failed at once), for testing the page's fallback.
"""
import argparse
import base64
import json
import os
import sys

import h5py
import numpy as np

SKIN_COLOR = "#e9b08f"
BONES_COLOR = "#f1ead6"
DEFAULT_PLOTS = ["knee_angle", "back_activation", "front_activation"]


def b64(array, dtype):
    a = np.ascontiguousarray(array, dtype=np.dtype(dtype).newbyteorder("<"))
    return base64.b64encode(a.tobytes()).decode("ascii")


def attr_str(attrs, key, default=""):
    if key not in attrs:
        return default
    v = attrs[key]
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    if isinstance(v, np.ndarray) and v.size == 1:
        v = v.reshape(()).item()
        if isinstance(v, bytes):
            return v.decode("utf-8", "replace")
    return str(v)


def mesh(fields, name, color, opacity, frames_sel):
    points = np.asarray(fields[name + "_points"][:], dtype=np.float64)
    tris = np.asarray(fields[name + "_triangles"][:], dtype=np.int64)
    V, T = points.shape[0], tris.shape[0]
    if tris.size and (tris.min() < 0 or tris.max() >= V):
        raise SystemExit(f"{name}: triangle index out of range")
    disp_name = name + "_displacement"
    if frames_sel is not None and disp_name in fields and len(frames_sel):
        disp = np.asarray(fields[disp_name][frames_sel, :, :], dtype=np.float64)
    else:
        disp = np.zeros((0, V, 3))
    peak = float(np.abs(disp).max()) if disp.size else 0.0
    scale = peak / 32767.0 if peak > 0 else 1e-6
    counts = np.clip(np.rint(disp / scale), -32767, 32767).astype(np.int16)
    return {
        "name": name,
        "color": color,
        "opacity": opacity,
        "vertices": int(V),
        "triangles": int(T),
        "triangles_b64": b64(tris.astype(np.uint32), "<u4"),
        "rest_b64": b64(points.astype(np.float32), "<f4"),
        "displacement_scale": scale,
        "displacement_b64": b64(counts, "<i2"),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run_dir")
    ap.add_argument("out")
    ap.add_argument("--every", type=int, default=4, help="keep every N-th frame (default 4)")
    ap.add_argument("--max-frames", type=int, default=0, help="keep at most N frames (0: all)")
    ap.add_argument("--plots", default=None, help="comma-separated default plot columns")
    ap.add_argument("--no-frames", action="store_true", help="write zero frames (failed-at-once fixture)")
    ap.add_argument("--status", default=None, help="override the status")
    ap.add_argument("--failure", default=None, help="override the failure text")
    args = ap.parse_args()

    path = os.path.join(args.run_dir, "leg.h5") if os.path.isdir(args.run_dir) else args.run_dir
    with h5py.File(path, "r") as f:
        fields = f["fields"]
        meta = f["meta"].attrs if "meta" in f else {}
        times_all = np.asarray(fields["skin_time"][:], dtype=np.float64)
        sel = np.arange(0, len(times_all), max(1, args.every))
        if args.max_frames > 0:
            sel = sel[: args.max_frames]
        if args.no_frames:
            sel = sel[:0]
        frame_times = times_all[sel]

        meshes = [mesh(fields, "skin", SKIN_COLOR, 0.55, sel)]
        if "bones_points" in fields and "bones_triangles" in fields:
            meshes.append(mesh(fields, "bones", BONES_COLOR, 1.0, sel))

        columns = []
        series_time = []
        if "series" in f:
            s = f["series"]
            n = len(s["time"]) if "time" in s else 0
            rows = sel if n == len(times_all) else np.arange(0, n, max(1, args.every))
            if args.no_frames:
                rows = rows[:0]
            if "time" in s:
                series_time = np.asarray(s["time"][:], dtype=np.float64)[rows].tolist()
            for key in sorted(s.keys()):
                if key == "time":
                    continue
                d = s[key]
                if not isinstance(d, h5py.Dataset) or d.ndim != 1 or len(d) != n:
                    continue
                vals = np.asarray(d[:], dtype=np.float64)[rows]
                columns.append({
                    "name": key,
                    "unit": attr_str(d.attrs, "units", attr_str(d.attrs, "unit", "")),
                    "values": [v if np.isfinite(v) else None for v in vals.tolist()],
                })

        scene = attr_str(meta, "spec_name", os.path.basename(os.path.abspath(args.run_dir)))
        variant = attr_str(meta, "variant", "")
        status = args.status or attr_str(meta, "status", "complete")
        failure = args.failure if args.failure is not None else attr_str(meta, "failure", "")

    names = [c["name"] for c in columns]
    plots = [p for p in (args.plots.split(",") if args.plots else DEFAULT_PLOTS) if p in names]
    if not plots and names:
        plots = names[:1]

    run = {
        "format": "tissuebench-view/1",
        "title": scene + (" / " + variant if variant else ""),
        "scene": scene,
        "variant": variant,
        "run_dir": os.path.abspath(args.run_dir),
        "status": status,
        "failure": failure,
        "frame_times": frame_times.tolist(),
        "meshes": meshes,
        "series": {"time": series_time, "columns": columns},
        "plots": plots,
    }
    with open(args.out, "w") as out:
        json.dump(run, out, separators=(",", ":"), allow_nan=False)
    print(f"{args.out}: {len(frame_times)} frames, {len(meshes)} meshes, "
          f"{len(columns)} series columns, {os.path.getsize(args.out)} bytes", file=sys.stderr)


if __name__ == "__main__":
    main()
