#!/usr/bin/python3
"""The leg in the suite's report: per leg scene run, its curves, a filmstrip of
the limb and the thesis' outcome beside the measured one.

make_report.py calls `leg_section(DIR, manifest)` for the scenes listed under
the manifest's "leg" key (DIR/suite.json; each run folder is what
`tissuebench leg SCENE.yaml --out DIR/leg/SCENE[/VARIANT]` writes:
docs/leg-scenes.md, "What a run writes"). Per run:

- the knee angle, the tendon tensions (per tendon, the sum over its strands)
  and the muscles' length ratios (with their activations) over time;
- a filmstrip: TILES frames evenly spread over the run, the skin translucent
  and the bones opaque, drawn offscreen (Agg, mplot3d) from one fixed side
  camera (x forward to the right, z up, looking along +y) with limits fixed
  over all frames. The bones are /fields/bones_* when the file has them, else
  the geometry's bone surfaces placed by the recorded knee angle (the femur is
  fixed in every scene; the lower bone turns about the knee's axis). Every tile
  is checked not blank; a blank one raises LegRenderError naming the scene,
  variant and frame;
- for a pendulum (drop) run: the knee angle against the damped pendulum that
  the published healthy values define (reports/leg_outcomes.yaml,
  `pendulum_reference`);
- the table of reports/leg_outcomes.yaml: what the thesis says, what the run
  measured (summary.json `values`).

Command line (Debian's python3-matplotlib, -h5py, -yaml; no pip):

  /usr/bin/python3 reports/leg_report.py --self-test RUN_DIR
          [--make-run TISSUEBENCH SCENE [--duration S]]
      With --make-run, first runs `TISSUEBENCH leg SCENE --out RUN_DIR
      --duration S` (default 1 s). Renders a filmstrip of the leg run in
      RUN_DIR (a folder with leg.h5, or a scene folder with variant
      sub-folders: the first one), checks that every tile is not blank and
      keeps the strip as RUN_DIR/self_test_filmstrip.png; then runs three
      negative controls that must each be caught as blank: the same frame with
      all geometry moved out of the fixed view, an empty figure, and a
      uniformly filled image. Exit 0 only when the real render passes and
      every control is caught; 1 otherwise.
  /usr/bin/python3 reports/leg_report.py --write-pngs RUN_DIR OUT_DIR
      writes the run's figures as PNG files (curves, filmstrip, pendulum) to
      look at.
  /usr/bin/python3 reports/leg_report.py --section SUITE_DIR
      builds the leg section of SUITE_DIR/suite.json and prints its timing.
"""
import argparse
import base64
import io
import json
import math
import os
import subprocess
import sys
import time

import h5py
import matplotlib
import numpy as np
import yaml

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d import proj3d  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from render_leg import read_obj  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
OUTCOMES_FILE = os.path.join(HERE, "leg_outcomes.yaml")
DEFAULT_GEOMETRY = os.path.join(HERE, "..", "msd", "data", "leg", "leg.yaml")

TILES = 6                      # frames per filmstrip
TILE_HEIGHT_PX = 360           # each tile's height; its width follows the view's aspect
TILE_DPI = 100
BACKGROUND = (1.0, 1.0, 1.0)   # the tiles' background (white)
SKIN_RGB = np.array([0.90, 0.64, 0.50])   # flesh
SKIN_ALPHA = 0.13
BONE_RGB = np.array([0.97, 0.95, 0.88])   # bone
OBSTACLE_RGB = np.array([0.44, 0.56, 0.69])   # a rigid obstacle (the viewer's blue)
BONE_EDGE_SHADE = 0.30         # the darkest a bone face gets (grazing light)
LIGHT = np.array([0.35, -1.0, 0.55])      # towards the light: from the camera's side, above, in front
MAX_FACES = 16000              # skin + bone triangles per tile before decimation (keeps a tile near 1 s)
VIEW = {"elev": 0.0, "azim": -90.0}       # side view: x to the right, z up, looking along +y
EYE = np.array([math.cos(math.radians(VIEW["elev"])) * math.cos(math.radians(VIEW["azim"])),
                math.cos(math.radians(VIEW["elev"])) * math.sin(math.radians(VIEW["azim"])),
                math.sin(math.radians(VIEW["elev"]))])   # towards the camera

# The non-blank check: a tile passes when at least MIN_FRACTION of its pixels
# differ from the background by more than COLOUR_TOLERANCE (of 255) in some
# channel, and those pixels hold at least MIN_COLOURS distinct colours.
MIN_FRACTION = 0.02
COLOUR_TOLERANCE = 8
MIN_COLOURS = 2


class LegRenderError(RuntimeError):
    """A filmstrip tile rendered blank (or the render could not be checked)."""


# ----------------------------------------------------------------------------
# small helpers

def png(fig, dpi=90):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def fmt(v, digits=3):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    if v != 0 and abs(v) >= 10 ** digits:
        return "%.0f" % v
    return ("%." + str(digits) + "g") % v


def load_json(path):
    with open(path) as f:
        return json.load(f)


def load_outcomes(path=OUTCOMES_FILE):
    with open(path) as f:
        return yaml.safe_load(f)


def rotation(axis, angle):
    """Rodrigues: rotation by `angle` (rad) about the unit `axis`."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)


def signed_volume(points, triangles):
    p = points[triangles]
    return float(np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6.0)


def decimate(points, triangles, max_faces):
    """Vertex clustering on a grid: returns (labels, faces, clusters) with
    len(faces) <= max_faces; a frame's cluster positions are the means of
    their vertices (`cluster_positions`). Identity when already small."""
    n = len(points)
    if len(triangles) <= max_faces:
        return np.arange(n), triangles, n
    lo, hi = points.min(axis=0), points.max(axis=0)
    cell = float(np.max(hi - lo)) / 400.0
    while True:
        keys = np.floor((points - lo) / cell).astype(np.int64)
        _, labels = np.unique(keys, axis=0, return_inverse=True)
        labels = labels.reshape(-1)
        f = labels[triangles]
        f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])]
        _, first = np.unique(np.sort(f, axis=1), axis=0, return_index=True)
        f = f[np.sort(first)]
        if len(f) <= max_faces:
            return labels, f, int(labels.max()) + 1
        cell *= 1.25


def cluster_positions(x, labels, clusters):
    counts = np.bincount(labels, minlength=clusters).astype(float)
    counts[counts == 0] = 1.0
    return np.stack([np.bincount(labels, weights=x[:, k], minlength=clusters) for k in range(3)], axis=1) / counts[:, None]


# ----------------------------------------------------------------------------
# a run's geometry over time

class LegFrames:
    """The skin and the bones of one leg run, frame by frame."""

    def __init__(self, h5path):
        self.path = h5path
        with h5py.File(h5path, "r") as f:
            self.status = str(f["meta"].attrs.get("status", "unknown"))
            self.spec = yaml.safe_load(f["meta"].attrs.get("spec", "")) or {}
            self.geometry_file = str(f["meta"].attrs.get("geometry", ""))
            self.series = {k: f["series"][k][()] for k in f["series"].keys()} if "series" in f else {}
            fl = f["fields"] if "fields" in f else {}
            if "skin_points" not in fl:
                raise KeyError("%s has no /fields/skin_points" % h5path)
            self.skin_points = fl["skin_points"][()]
            self.skin_tris = fl["skin_triangles"][()].astype(np.int64)
            self.skin_time = fl["skin_time"][()]
            self.has_bone_fields = all(k in fl for k in ("bones_points", "bones_triangles",
                                                        "bones_displacement", "bones_time"))
            if self.has_bone_fields:
                self.bone_points = fl["bones_points"][()]
                self.bone_tris = fl["bones_triangles"][()].astype(np.int64)
                self.bone_time = fl["bones_time"][()]
            # the obstacles as the run drew them (a piece of each cylinder, a square of each plane)
            self.obstacle_points = fl["obstacles_points"][()] if "obstacles_points" in fl else None
            self.obstacle_tris = fl["obstacles_triangles"][()].astype(np.int64) if "obstacles_triangles" in fl else None
        self.bones_note = "bones: /fields/bones_*"
        if not self.has_bone_fields:
            self._bones_from_geometry()
        if self.bone_points is not None and signed_volume(self.bone_points, self.bone_tris) < 0:
            self.bone_tris = self.bone_tris[:, ::-1].copy()   # outward normals, for back-face culling
        # Keep each tile's triangle count within MAX_FACES: decimate the skin first.
        bone_faces = len(self.bone_tris) if self.bone_points is not None else 0
        bone_budget = min(bone_faces, MAX_FACES // 2)
        self.bone_map = decimate(self.bone_points, self.bone_tris, bone_budget) if bone_faces else None
        self.skin_map = decimate(self.skin_points, self.skin_tris, MAX_FACES - bone_budget)

    def _bones_from_geometry(self):
        """The geometry's bone surfaces, placed by the knee angle (the femur
        is fixed in every scene, the lower bone turns about the knee axis)."""
        self.bone_points = None
        self.bone_tris = None
        geo = self.geometry_file if os.path.exists(self.geometry_file) else DEFAULT_GEOMETRY
        try:
            with open(geo) as f:
                leg = (yaml.safe_load(f) or {}).get("leg", {})
            base = os.path.dirname(os.path.abspath(geo))
            upper, upper_f = read_obj(os.path.join(base, leg["upper_bone"]))
            lower, lower_f = read_obj(os.path.join(base, leg["lower_bone"]))
        except (OSError, KeyError, ValueError, TypeError) as e:
            self.bones_note = "bones: not drawn (%s)" % e
            return
        knee = self.spec.get("knee", {}) or {}
        self.knee_centre = np.array(knee.get("centre", [0.0, 0.0, 0.50046]), dtype=float)
        self.knee_axis = np.array(knee.get("axis", [0.0, 1.0, 0.0]), dtype=float)
        self.bone_points = np.concatenate([upper, lower])
        self.bone_tris = np.concatenate([upper_f, lower_f + len(upper)])
        self.n_upper = len(upper)
        self.bone_time = self.skin_time
        self.bones_note = ("bones: the geometry's surfaces (%s) placed by the recorded knee angle "
                           "(this leg.h5 has no /fields/bones_*)" % os.path.basename(geo))

    def frames(self):
        return len(self.skin_time)

    def knee_angle_at(self, t):
        s = self.series
        if "knee_angle" not in s or "time" not in s or not len(s["time"]):
            return 0.0
        return float(np.interp(t, s["time"], s["knee_angle"]))

    def _displaced(self, name, rest, j, f=None):
        """rest + /fields/NAME_displacement[j], from `f` or the file opened for it."""
        if f is None:
            with h5py.File(self.path, "r") as g:
                return self._displaced(name, rest, j, g)
        return rest + f["fields/%s_displacement" % name][j]

    def skin(self, i, f=None):
        return self._displaced("skin", self.skin_points, i, f)

    def bones(self, i, f=None):
        if self.bone_points is None:
            return None
        t = self.skin_time[i]
        if self.has_bone_fields:
            return self._displaced("bones", self.bone_points, int(np.argmin(np.abs(self.bone_time - t))), f)
        x = self.bone_points.copy()
        r = rotation(self.knee_axis, math.radians(self.knee_angle_at(t)))
        x[self.n_upper:] = (x[self.n_upper:] - self.knee_centre) @ r.T + self.knee_centre
        return x

    def obstacles(self, i, f):
        """The obstacles' surfaces at frame i (None when the run has none)."""
        if self.obstacle_points is None or "fields/obstacles_displacement" not in f:
            return None
        return self._displaced("obstacles", self.obstacle_points, min(i, f["fields/obstacles_displacement"].shape[0] - 1), f)

    def limits(self):
        """Bounding box of skin and bones over every frame (finite values)."""
        lo = np.full(3, np.inf)
        hi = np.full(3, -np.inf)
        with h5py.File(self.path, "r") as f:
            ds = f["fields/skin_displacement"]
            for a in range(0, ds.shape[0], 128):
                x = (self.skin_points[None] + ds[a:a + 128]).reshape(-1, 3)
                if not np.isfinite(x).all():
                    x = x[np.isfinite(x).all(axis=1)]
                if len(x):
                    lo = np.minimum(lo, x.min(axis=0))
                    hi = np.maximum(hi, x.max(axis=0))
            if self.bone_points is not None:
                for i in range(0, self.frames(), max(1, self.frames() // 50)):
                    b = self.bones(i, f)
                    b = b[np.isfinite(b).all(axis=1)]
                    if len(b):
                        lo = np.minimum(lo, b.min(axis=0))
                        hi = np.maximum(hi, b.max(axis=0))
        pad = 0.03 * float(np.max(hi - lo))
        return lo - pad, hi + pad


# ----------------------------------------------------------------------------
# rendering and the non-blank check

def shaded(polys, rgb, alpha, floor):
    """Per-face RGBA: two-sided Lambert light from LIGHT."""
    n = np.cross(polys[:, 1] - polys[:, 0], polys[:, 2] - polys[:, 0])
    n /= np.linalg.norm(n, axis=1)[:, None] + 1e-30
    light = LIGHT / np.linalg.norm(LIGHT)
    s = floor + (1.0 - floor) * np.abs(n @ light)
    c = np.empty((len(polys), 4))
    c[:, :3] = np.clip(rgb[None, :] * s[:, None], 0, 1)
    c[:, 3] = alpha
    return c


def render_tile(skin_xyz, skin_faces, bone_xyz, bone_faces, lo, hi, obstacle_xyz=None, obstacle_faces=None):
    """One frame, offscreen: an (H, W, 3) uint8 image on the BACKGROUND,
    cropped to the box [lo, hi] as the camera sees it (so every frame of a
    strip, drawn with the same box, has the same size and framing)."""
    ext = hi - lo
    # mplot3d draws in the largest centred square; size it so that the box's
    # projection (x across, z up) gets about TILE_HEIGHT_PX along z.
    side = int(round(TILE_HEIGHT_PX * max(1.0, float(ext[0] / ext[2])) / 0.78))
    fig = plt.figure(figsize=(side / TILE_DPI, side / TILE_DPI), dpi=TILE_DPI, facecolor=BACKGROUND)
    ax = fig.add_axes([0, 0, 1, 1], projection="3d", facecolor=BACKGROUND)
    ax.set_proj_type("ortho")
    ax.view_init(**VIEW)
    polys, colours = [], []
    if bone_xyz is not None and bone_faces is not None and len(bone_faces):
        p = bone_xyz[bone_faces]
        # Opaque and closed, with outward normals: the faces turned away from the camera are hidden.
        p = p[np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]) @ EYE > 0]
        polys.append(p)
        colours.append(shaded(p, BONE_RGB, 1.0, BONE_EDGE_SHADE))
    if obstacle_xyz is not None and obstacle_faces is not None and len(obstacle_faces):
        p = obstacle_xyz[obstacle_faces]
        polys.append(p)
        colours.append(shaded(p, OBSTACLE_RGB, 0.85, 0.5))
    if skin_xyz is not None and len(skin_faces):
        p = skin_xyz[skin_faces]
        polys.append(p)
        colours.append(shaded(p, SKIN_RGB, SKIN_ALPHA, 0.55))
    if polys:
        # One collection, so that skin and bone faces are depth-sorted together.
        ax.add_collection3d(Poly3DCollection(np.concatenate(polys), facecolors=np.concatenate(colours),
                                             edgecolors="none", linewidths=0, antialiased=False))
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(ext))  # true proportions
    ax.set_axis_off()
    fig.canvas.draw()
    img = np.asarray(fig.canvas.buffer_rgba())[:, :, :3].copy()
    # Crop to the box's corners as projected (display pixels, origin at the bottom left).
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    px, py, _ = proj3d.proj_transform(corners[:, 0], corners[:, 1], corners[:, 2], ax.M)
    disp = ax.transData.transform(np.column_stack([px, py]))
    plt.close(fig)
    h = img.shape[0]
    c0, c1 = int(math.floor(disp[:, 0].min())), int(math.ceil(disp[:, 0].max()))
    r0, r1 = int(math.floor(h - disp[:, 1].max())), int(math.ceil(h - disp[:, 1].min()))
    c0, r0 = max(c0, 0), max(r0, 0)
    c1, r1 = min(c1, img.shape[1]), min(r1, h)
    if c1 - c0 < 8 or r1 - r0 < 8:
        raise LegRenderError("the view box [%s, %s] projects to %dx%d pixels" % (lo, hi, c1 - c0, r1 - r0))
    return img[r0:r1, c0:c1]


def blank_stats(img, background=BACKGROUND):
    """(fraction of pixels off the background, distinct colours among them)."""
    bg = np.round(np.asarray(background) * 255).astype(int)
    diff = np.abs(img.astype(int) - bg[None, None, :]).max(axis=2) > COLOUR_TOLERANCE
    fraction = float(diff.mean())
    if not diff.any():
        return fraction, 0
    px = img[diff].astype(np.int64)
    colours = len(np.unique(px[:, 0] * 65536 + px[:, 1] * 256 + px[:, 2]))
    return fraction, colours


def is_blank(img, background=BACKGROUND):
    fraction, colours = blank_stats(img, background)
    return fraction < MIN_FRACTION or colours < MIN_COLOURS


def check_tile(img, what):
    fraction, colours = blank_stats(img)
    if fraction < MIN_FRACTION or colours < MIN_COLOURS:
        raise LegRenderError("%s rendered blank: %.2f %% of its pixels differ from the background "
                             "(at least %.0f %% needed), %d distinct colour(s) (at least %d needed)"
                             % (what, 100 * fraction, 100 * MIN_FRACTION, colours, MIN_COLOURS))
    return fraction


def frame_indices(n, tiles=TILES, frame_times=None, knee=None):
    """The frames of a strip: the first, the knee's most flexed and most
    extended, its turning points (those that end its largest swings first), the last; filled up evenly when the knee turns fewer times
    than the strip has room for. Without a knee series: evenly spread."""
    if n <= 0:
        return []
    even = [int(round(x)) for x in np.linspace(0, n - 1, min(tiles, n))]
    if frame_times is None or knee is None or len(knee[0]) < 3:
        return sorted(set(even))
    t, a = knee
    at = np.interp(frame_times, t, a)
    # a turning point counts when the knee swung at least 5 % of its range
    # (and 2 degrees) since the last one that counted: wiggles on a plateau do not
    least = max(2.0, 0.05 * float(np.ptp(at)))
    turns, swing, last = [], {}, at[0]
    for i in range(1, n - 1):
        if (at[i] - at[i - 1]) * (at[i + 1] - at[i]) < 0 and abs(at[i] - last) >= least:
            turns.append(i)
            swing[i] = abs(at[i] - last)
            last = at[i]
    turns.sort(key=lambda i: -swing[i])
    chosen = {0, n - 1, int(np.argmax(at)), int(np.argmin(at))}
    for i in turns:
        if len(chosen) >= tiles:
            break
        chosen.add(i)
    for i in even:
        if len(chosen) >= tiles:
            break
        chosen.add(i)
    return sorted(chosen)


def render_frames(legf, indices, lo, hi, shift=None):
    """Tiles for the given frames; `shift` moves all geometry (negative control)."""
    s_labels, s_faces, s_n = legf.skin_map
    tiles = []
    with h5py.File(legf.path, "r") as f:
        for i in indices:
            x = cluster_positions(legf.skin(i, f), s_labels, s_n)
            b, b_faces = None, None
            if legf.bone_map is not None:
                b_labels, b_faces, b_n = legf.bone_map
                b = cluster_positions(legf.bones(i, f), b_labels, b_n)
            o = legf.obstacles(i, f)
            if shift is not None:
                x = x + shift
                b = None if b is None else b + shift
                o = None if o is None else o + shift
            tiles.append(render_tile(x, s_faces, b, b_faces, lo, hi, o, legf.obstacle_tris))
    return tiles


def filmstrip(legf, what, tiles=TILES):
    """The filmstrip figure (PNG data URI) and its notes; raises LegRenderError
    when a tile is blank."""
    n = legf.frames()
    knee = None
    if "knee_angle" in legf.series and "time" in legf.series:
        knee = (np.asarray(legf.series["time"]), np.asarray(legf.series["knee_angle"]))
    idx = frame_indices(n, tiles, np.asarray(legf.skin_time[:n]), knee)
    if not idx:
        return None, "no frames were written"
    # Frames with non-finite positions are left out (a failed run's last frames).
    with h5py.File(legf.path, "r") as f:
        ds = f["fields/skin_displacement"]
        idx = [i for i in idx if np.isfinite(ds[i]).all()]
    if not idx:
        return None, "no frame with finite positions among those picked"
    lo, hi = legf.limits()
    imgs = render_frames(legf, idx, lo, hi)
    fractions = []
    for i, img in zip(idx, imgs):
        fractions.append(check_tile(img, "%s: frame %d (t = %.3f s)" % (what, i, legf.skin_time[i])))
    h, w = imgs[0].shape[:2]
    cols = len(imgs) if len(imgs) <= 3 or w > h else (len(imgs) + 1) // 2
    nrows = (len(imgs) + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(cols * w / 90.0, nrows * (h / 90.0 + 0.35)), squeeze=False)
    axes = axes.ravel()
    for ax in axes[len(imgs):]:
        ax.set_axis_off()
    for ax, i, img in zip(axes, idx, imgs):
        ax.imshow(img, interpolation="nearest")
        ax.set_title("t = %.2f s, knee %.0f°" % (legf.skin_time[i], legf.knee_angle_at(legf.skin_time[i])), fontsize=10)
        ax.set_xticks([])
        ax.set_yticks([])
        for sp in ax.spines.values():
            sp.set_color("0.8")
    g = legf.spec.get("gravity", [0, 0, -9.81])
    gx, gz = float(g[0]), float(g[2])
    if math.hypot(gx, gz) > 0:
        ux, uz = gx / math.hypot(gx, gz), gz / math.hypot(gx, gz)
        ax0 = axes[0]
        cx, cy = 0.12, 0.86
        ax0.annotate("", xy=(cx + 0.08 * ux, cy + 0.08 * uz), xytext=(cx - 0.08 * ux, cy - 0.08 * uz),
                     xycoords="axes fraction", arrowprops=dict(arrowstyle="->", color="0.3", lw=1.2))
        ax0.text(cx + 0.05, cy + 0.05, "g", transform=ax0.transAxes, fontsize=8, color="0.3")
    fig.subplots_adjust(wspace=0.03, hspace=0.12, left=0.005, right=0.995, top=1 - 0.3 / fig.get_figheight(),
                        bottom=0.01)
    note = ("%d of %d frames: the first, the knee's most flexed and most extended, its turning points (those "
            "ending its largest swings), the last, filled up evenly; one camera for the strip: side view (x forward to the right, z up, "
            "looking along +y, orthographic), limits fixed over all frames; skin translucent, bones opaque, obstacles (if any) blue; "
            "the arrow is gravity. %s. Skin %d of %d triangles drawn. Every tile checked not blank "
            "(%s %% of its pixels off the background)."
            % (len(idx), n, legf.bones_note, len(legf.skin_map[1]), len(legf.skin_tris),
               "%.0f" % (100 * min(fractions)) if round(100 * min(fractions)) == round(100 * max(fractions))
               else "%.0f-%.0f" % (100 * min(fractions), 100 * max(fractions))))
    return png(fig), note


# ----------------------------------------------------------------------------
# curves

def curves_figure(legf, title, failure_time=None):
    s = legf.series
    t = s.get("time")
    if t is None or not len(t) or "knee_angle" not in s:
        return None
    tendons = sorted(k for k in s if k.startswith("tension_"))
    lengths = sorted(k for k in s if k.startswith("length_ratio_"))
    probe = [k for k in ("probe_x", "probe_y", "probe_z") if k in s]
    rows = 3 + (1 if probe else 0)
    fig, axes = plt.subplots(rows, 1, figsize=(6.6, 1.9 * rows + 0.5), sharex=True)
    ax = axes[0]
    ax.plot(t, s["knee_angle"], "k-", lw=1.4, label="knee angle")
    ax.set_ylabel("knee angle (°)")
    ax.set_title(title, fontsize=10)
    ax = axes[1]
    for k in tendons:
        ax.plot(t, s[k], lw=1.1, label=k[len("tension_"):].replace("_", " "))
    ax.set_ylabel("tendon tension (N)")
    if tendons:
        ax.legend(fontsize=7, ncol=2, loc="upper right")
    ax = axes[2]
    colours = {"front": "tab:red", "back": "tab:purple"}
    for k in lengths:
        m = k[len("length_ratio_"):]
        ax.plot(t, s[k], lw=1.2, color=colours.get(m.split("_")[0]), label="%s length ratio" % m.replace("_", " "))
    for m in ("front", "back"):
        key = m + "_activation"
        if key in s and np.any(s[key] != 0):
            ax.plot(t, s[key], lw=1.0, ls="--", color=colours[m], label="%s activation" % m)
    ax.set_ylabel("ratio, activation (1)")
    ax.legend(fontsize=7, ncol=2, loc="lower left")
    if probe:
        ax = axes[3]
        for k in probe:
            ax.plot(t, 1e3 * s[k], lw=0.9, label=k.replace("_", " "))
        ax.set_ylabel("probe displacement (mm)")
        ax.legend(fontsize=7, ncol=3, loc="upper right")
    for ax in axes:
        ax.grid(alpha=0.3)
        if failure_time is not None:
            ax.axvline(failure_time, color="tab:red", lw=1.2)
    if failure_time is not None:
        axes[0].text(failure_time, axes[0].get_ylim()[1], " blew up", color="tab:red", fontsize=8, va="top")
    axes[-1].set_xlabel("time t (s)")
    fig.tight_layout()
    return png(fig)


# ----------------------------------------------------------------------------
# the pendulum test against the published healthy one

def zeta_from_ri(ri):
    """Damping ratio of a linear oscillator whose relaxation index (first swing
    over start-to-rest) is `ri`: ri = 1 + exp(-pi zeta / sqrt(1 - zeta^2))."""
    r = ri - 1.0
    d = -math.log(r)
    return d / math.sqrt(math.pi ** 2 + d ** 2)


def damped(tau, rest, start, period, zeta):
    """Free response of a linear damped oscillator released at rest at `start`;
    `period` is the damped period."""
    wd = 2 * math.pi / period
    wn = wd / math.sqrt(1 - zeta ** 2)
    a = start - rest
    return rest + a * np.exp(-zeta * wn * tau) * (np.cos(wd * tau) + zeta / math.sqrt(1 - zeta ** 2) * np.sin(wd * tau))


def extrema(t, y, rest, min_deg=0.5):
    """Alternating extremes of y about `rest` (local maxima above, minima below)."""
    out = []
    for i in range(1, len(y) - 1):
        if y[i] >= y[i - 1] and y[i] > y[i + 1] and y[i] - rest > min_deg:
            out.append((t[i], y[i]))
        elif y[i] <= y[i - 1] and y[i] < y[i + 1] and rest - y[i] > min_deg:
            out.append((t[i], y[i]))
    return out


def pendulum_figure(legf, values, ref, release, complete=True):
    s = legf.series
    if "time" not in s or "knee_angle" not in s:
        return None, None
    t, a = s["time"], s["knee_angle"]
    after = t >= release - 1e-9
    if after.sum() < 5:
        return None, None
    t0 = float(t[after][0])
    a0 = float(a[after][0])
    if "lower_leg_below_horizontal" in s:
        offset = float(np.median(a[after] - s["lower_leg_below_horizontal"][after]))
        plumb = 90.0 + offset
        plumb_note = ("the knee angle at which the lower leg hangs plumb, %.1f° (90° plus the run's median "
                      "knee angle minus lower-leg angle below horizontal)" % plumb)
    else:
        plumb = 90.0
        plumb_note = "90° (lower leg plumb below a horizontal thigh)"
    trace = ref["trace"]
    period = float(np.mean(trace["periods_s"]))
    ri = ref["relaxation_index"]
    z_mid = zeta_from_ri(ri["mean"])
    z_lo, z_hi = zeta_from_ri(ri["mean"] + ri["sd"]), zeta_from_ri(ri["mean"] - ri["sd"])
    tau = np.linspace(0.0, max(float(t[-1]) - t0, 4 * period), 800)
    band = np.array([damped(tau, plumb, a0, period, z) for z in np.linspace(z_lo, z_hi, 25)])
    mid = damped(tau, plumb, a0, period, z_mid)

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10.5, 3.8), gridspec_kw={"width_ratios": [2.1, 1]})
    ax.fill_between(t0 + tau, band.min(axis=0), band.max(axis=0), color="tab:green", alpha=0.18, lw=0,
                    label="healthy: ζ %.3f-%.3f (RI %.3f ± %.3f [K])" % (z_lo, z_hi, ri["mean"], ri["sd"]))
    ax.plot(t0 + tau, mid, color="tab:green", lw=1.4, label="healthy: ζ %.3f, T %.2f s [K, T]" % (z_mid, period))
    ax.axhline(plumb, color="tab:green", lw=0.8, ls=":")
    ax.plot(t, a, "k-", lw=1.5, label="model (this run)")
    rest = None
    if complete:  # the swing's centre where the run has one (null when not finite), else the end's mean
        rest = values.get("drop_swing_centre_deg")
        if rest is None:
            rest = values.get("drop_rest_angle_deg")
    if rest is not None:
        ax.axhline(rest, color="k", lw=0.8, ls=":")
    ax.axvline(t0, color="0.5", lw=0.8, ls="--")
    ax.text(t0, ax.get_ylim()[0], " release", fontsize=8, color="0.4", va="bottom")
    ax.set_xlabel("time t (s)")
    ax.set_ylabel("knee angle (°, flexion +)")
    ax.set_title("pendulum test: the model against healthy legs", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="lower right")

    # Time-free: each extreme's distance from rest over the start's distance from rest.
    rest_m = rest if rest is not None else float(np.mean(a[after][-max(1, after.sum() // 5):]))
    ext = extrema(t[after], a[after], rest_m) if complete else []
    ks = np.arange(1, 12)
    r_mid, r_lo, r_hi = ri["mean"] - 1, ri["mean"] - ri["sd"] - 1, ri["mean"] + ri["sd"] - 1
    bx.fill_between(ks, r_lo ** ks, r_hi ** ks, color="tab:green", alpha=0.18, lw=0)
    bx.plot(ks, r_mid ** ks, color="tab:green", lw=1.2, label="linear, RI %.3f ± %.3f [K]" % (ri["mean"], ri["sd"]))
    span_t = abs(trace["start_rad"] - trace["end_rad"])
    tk = [(1, trace["flexion_peaks_rad"][0]), (2, trace["first_extension_peak_rad"])]
    tk += [(2 * j + 1, p) for j, p in enumerate(trace["flexion_peaks_rad"]) if j > 0]
    bx.plot([k for k, _ in tk], [abs(p - trace["end_rad"]) / span_t for k, p in tk], "s", color="tab:blue",
            ms=5, label="typical trace [T]")
    if ext and abs(a0 - rest_m) > 1e-9:
        bx.plot(np.arange(1, len(ext) + 1), [abs(y - rest_m) / abs(a0 - rest_m) for _, y in ext], "ko-", ms=4,
                lw=0.8, label="model")
    bx.set_yscale("log")
    bx.set_xlabel("half-swing k (1: first flexion peak)")
    bx.set_ylabel("|extreme − rest| / |start − rest|")
    bx.set_title("decay per half swing", fontsize=10)
    bx.grid(alpha=0.3, which="both")
    bx.legend(fontsize=7)
    fig.tight_layout()
    ri_trace = (trace["flexion_peaks_rad"][0] - trace["start_rad"]) / (trace["end_rad"] - trace["start_rad"])
    caption = (
        "Left: the run's knee angle (black) and the pendulum response the published healthy values define "
        "(green): the free response of a linear damped oscillator started at the run's own release "
        "(t = %.2f s, %.1f°) and relaxing to %s, assuming a relaxed leg comes to rest hanging. Its damped "
        "period is %.2f s, the mean of the first three cycles of trace [T] (%s s); its damping ratio ζ %.3f "
        "follows from the mean relaxation index of %d healthy adults [K] (for a linear oscillator "
        "RI = 1 + exp(-πζ/√(1-ζ²))), the band from RI ± 1 SD (ζ %.3f to %.3f). No digitised healthy curve "
        "was available: the green curve is this model of the published numbers, not a measured trace, and "
        "no published spread of the period was found (the band is the damping's spread only). Real legs are "
        "not linear: trace [T] loses less on its first swing (RI %.2f) and more on the next half swing. "
        "Dotted lines: the run's rest angle (black: the centre its swing decays towards) and the plumb (green). Right: each extreme's distance "
        "from rest over the start's, by half swing: the model (about its own rest), trace [T]'s published "
        "extremes (its first four flexion peaks and first extension peak; start %.2f rad, end %.3f rad), and "
        "the linear oscillator with RI ± 1 SD [K]."
        % (t0, a0, plumb_note, period, ", ".join("%.2f" % p for p in trace["periods_s"]), z_mid, int(ri["n"]),
           z_lo, z_hi, ri_trace, trace["start_rad"], trace["end_rad"]))
    if not complete:
        caption += (" The run failed at t = %.3f s: it has no rest angle, so its dotted line and its extremes are "
                    "not drawn." % float(t[-1]))
    return png(fig), caption


# ----------------------------------------------------------------------------
# the outcomes table

def measure_value(m, values):
    if "value" in m:
        v = values.get(m["value"])
    else:
        names = {k: float(v) for k, v in values.items() if isinstance(v, (int, float))}
        try:
            v = eval(m["expr"], {"__builtins__": {}}, names)  # noqa: S307 - repo data file, arithmetic only
        except (NameError, ZeroDivisionError, SyntaxError, TypeError):
            v = None
    if v is None:
        return None
    return float(v) * float(m.get("scale", 1.0))


def outcome_rows(spec, run_values):
    rows = []
    for m in spec.get("measures", []):
        rows.append({
            "label": m["label"], "unit": m.get("unit", ""), "thesis": m.get("thesis", "not stated"),
            "key": bool(m.get("key")),
            "measured": [fmt(measure_value(m, v), int(m.get("digits", 3))) if v is not None else "–"
                         for v in run_values],
        })
    return rows


# ----------------------------------------------------------------------------
# what a run wrote (for failed runs)

def written(run_dir):
    out = []
    if not os.path.isdir(run_dir):
        return ["nothing: %s does not exist" % run_dir]
    for name in sorted(os.listdir(run_dir)):
        p = os.path.join(run_dir, name)
        if os.path.isdir(p):
            n = len(os.listdir(p))
            out.append("%s/ (%d file%s)" % (name, n, "" if n == 1 else "s"))
            continue
        size = os.path.getsize(p)
        text = "%s (%s)" % (name, ("%.1f MB" % (size / 1e6)) if size >= 1e5 else ("%d bytes" % size))
        if name.endswith(".h5"):
            try:
                with h5py.File(p, "r") as f:
                    st = f["meta"].attrs.get("status", "?")
                    n = f["fields/skin_time"].shape[0] if "fields/skin_time" in f else 0
                    last = float(f["series/time"][-1]) if "series/time" in f and f["series/time"].shape[0] else None
                text += ": status %s, %d frame%s%s" % (st, n, "" if n == 1 else "s",
                                                      "" if last is None else ", last at t = %.3f s" % last)
            except (OSError, KeyError) as e:
                text += ": unreadable (%s)" % e
        out.append(text)
    return out


# ----------------------------------------------------------------------------
# the section

def release_time(legf, values):
    spec = legf.spec
    r = ((spec.get("analysis") or {}).get("drop") or {}).get("release")
    if r is None:
        r = (spec.get("knee") or {}).get("release")
    return float(r) if r is not None else 0.0


def run_section(d, scene, run, outcomes, timings):
    run_dir = os.path.join(d, run.get("dir") or scene["dir"])
    variant = run.get("variant") or ""
    what = "leg scene %s%s" % (scene["scene"], (", variant " + variant) if variant else "")
    summary_path = os.path.join(run_dir, "summary.json")
    summary = load_json(summary_path) if os.path.exists(summary_path) else {}
    values = summary.get("values", {}) or {}
    status = run.get("status") or summary.get("status") or "unknown"
    wall = run.get("wall_per_simulated_second", summary.get("wall_per_simulated_second"))
    out = {"variant": variant, "status": status, "failure": run.get("failure") or summary.get("failure") or "",
           "wall": fmt(wall, 3), "wall_value": wall, "simulated": fmt(summary.get("simulated_seconds"), 3),
           "dir": os.path.relpath(run_dir, d), "values": values if summary else None,
           "figure": None, "filmstrip": None, "filmstrip_note": "", "pendulum": None, "pendulum_caption": "",
           "notes": [], "written": written(run_dir) if status != "complete" else []}
    h5 = os.path.join(run_dir, "leg.h5")
    if not os.path.exists(h5):
        out["notes"].append("no leg.h5 in %s" % out["dir"])
        return out
    t_start = time.time()
    try:
        legf = LegFrames(h5)
    except (OSError, KeyError) as e:
        out["notes"].append("leg.h5 could not be read: %s" % e)
        return out
    failure_time = None
    if status != "complete" and len(legf.series.get("time", [])):
        failure_time = float(legf.series["time"][-1])
    title = "%s%s" % (scene["scene"], (" (" + variant + ")") if variant else "")
    out["figure"] = curves_figure(legf, title, failure_time)
    t_curves = time.time()
    out["filmstrip"], out["filmstrip_note"] = filmstrip(legf, what)
    t_strip = time.time()
    if any(k.startswith("drop_") for k in values) or (legf.spec.get("analysis") or {}).get("drop") is not None:
        ref = outcomes.get("pendulum_reference")
        if ref:
            out["pendulum"], out["pendulum_caption"] = pendulum_figure(legf, values, ref, release_time(legf, values),
                                                                       status == "complete")
    timings.append({"run": title, "curves": t_curves - t_start, "filmstrip": t_strip - t_curves,
                    "pendulum": time.time() - t_strip})
    return out


def scene_section(d, scene, outcomes, timings):
    spec = (outcomes.get("scenes") or {}).get(scene["scene"], {})
    runs = scene.get("runs") or [{"variant": "", "dir": scene["dir"], "status": scene.get("status")}]
    run_out = [run_section(d, scene, r, outcomes, timings) for r in runs]
    rows = outcome_rows(spec, [r["values"] for r in run_out])
    key = next((r for r in rows if r["key"]), rows[0] if rows else None)
    columns = [r["variant"] or "measured" for r in run_out]
    headers = [c + ("" if r["status"] == "complete" else " (run failed: over the frames written)")
               for c, r in zip(columns, run_out)]
    key_text = None
    if key:
        measured = ", ".join(("%s %s" % (c, m) if len(columns) > 1 else m) for c, m in zip(columns, key["measured"]))
        unit = "" if key["unit"] == "1" or all(m == "–" for m in key["measured"]) else \
            (key["unit"] if key["unit"] == "°" else " " + key["unit"])
        key_text = "%s %s%s; %s: %s" % (key["label"], measured, unit,
                                        "published" if spec.get("published") else "thesis", key["thesis"])
    return {
        "name": scene["scene"], "scene_file": scene.get("scene_file", ""), "dir": scene.get("dir", ""),
        "status": scene.get("status") or ("complete" if all(r["status"] == "complete" for r in run_out) else "failed"),
        "section": spec.get("section", "not in reports/leg_outcomes.yaml"), "lines": spec.get("lines", ""),
        "statement": (spec.get("statement") or "").strip(), "published": bool(spec.get("published")),
        "runs": run_out, "columns": headers, "rows": rows, "key": key_text,
        "wall": ", ".join(("%s %s" % (r["variant"], r["wall"]) if r["variant"] else r["wall"]) for r in run_out),
    }


def leg_section(d, manifest):
    """Per leg scene of the manifest (its "leg" list), a dict for the
    templates; [] when the suite ran none. Raises LegRenderError when a
    filmstrip tile renders blank."""
    entries = (manifest or {}).get("leg") or []
    if not entries:
        return []
    outcomes = load_outcomes()
    timings = []
    scenes = [scene_section(d, s, outcomes, timings) for s in entries]
    for s in scenes:
        s["timings"] = [t for t in timings if t["run"].split(" (")[0] == s["name"]]
    return scenes


def pendulum_sources():
    ref = load_outcomes().get("pendulum_reference") or {}
    return [(k, " ".join(str(v).split())) for k, v in (ref.get("sources") or {}).items()]


# ----------------------------------------------------------------------------
# command line

def find_run(path):
    if os.path.exists(os.path.join(path, "leg.h5")):
        return path
    for name in sorted(os.listdir(path)):
        if os.path.exists(os.path.join(path, name, "leg.h5")):
            return os.path.join(path, name)
    raise SystemExit("no leg.h5 in %s or its sub-folders" % path)


def self_test(path):
    run_dir = find_run(path)
    ok = True
    t0 = time.time()
    legf = LegFrames(os.path.join(run_dir, "leg.h5"))
    # 1. The real filmstrip: every tile must pass (filmstrip raises otherwise).
    try:
        uri, note = filmstrip(legf, "self-test %s" % run_dir)
        keep = os.path.join(run_dir, "self_test_filmstrip.png")
        with open(keep, "wb") as f:
            f.write(base64.b64decode(uri.split(",", 1)[1]))
        print("ok: the filmstrip of %s is not blank (%.1f s; kept as %s): %s" % (run_dir, time.time() - t0, keep, note))
    except LegRenderError as e:
        print("FAIL: %s" % e)
        ok = False
    lo, hi = legf.limits()
    mid = frame_indices(legf.frames(), 3)[len(frame_indices(legf.frames(), 3)) // 2]
    # 2. Negative controls: each must be found blank.
    far = np.array([10.0 * float(np.max(hi - lo)) + 10.0, 0.0, 0.0])
    controls = {
        "the same frame with all geometry moved out of view": render_frames(legf, [mid], lo, hi, shift=far)[0],
        "an empty figure": render_tile(None, np.zeros((0, 3), int), None, None, lo, hi),
    }
    real = render_frames(legf, [mid], lo, hi)[0]
    controls["a uniformly filled image"] = np.full_like(real, 200)
    for name, img in controls.items():
        fraction, colours = blank_stats(img)
        try:
            check_tile(img, "negative control: " + name)
            print("FAIL: the negative control (%s) passed the check (%.2f %% off the background, %d colours)"
                  % (name, 100 * fraction, colours))
            ok = False
        except LegRenderError as e:
            print("ok: caught: %s" % e)
    print("self-test %s" % ("passed" if ok else "FAILED"))
    return 0 if ok else 1


def write_pngs(path, out):
    run_dir = find_run(path) if not os.path.exists(os.path.join(path, "leg.h5")) else path
    os.makedirs(out, exist_ok=True)
    legf = LegFrames(os.path.join(run_dir, "leg.h5"))
    summary_path = os.path.join(run_dir, "summary.json")
    summary = load_json(summary_path) if os.path.exists(summary_path) else {}
    values = summary.get("values", {}) or {}
    complete = summary.get("status", legf.status) == "complete"
    failure_time = None if complete or not len(legf.series.get("time", [])) else float(legf.series["time"][-1])
    figs = {"curves": curves_figure(legf, os.path.basename(os.path.normpath(run_dir)), failure_time),
            "filmstrip": filmstrip(legf, run_dir)[0]}
    if any(k.startswith("drop_") for k in values):
        figs["pendulum"] = pendulum_figure(legf, values, load_outcomes()["pendulum_reference"],
                                           release_time(legf, values), complete)[0]
    for name, uri in figs.items():
        if uri:
            p = os.path.join(out, name + ".png")
            with open(p, "wb") as f:
                f.write(base64.b64decode(uri.split(",", 1)[1]))
            print("written:", p)
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--self-test", metavar="RUN_DIR")
    g.add_argument("--write-pngs", nargs=2, metavar=("RUN_DIR", "OUT_DIR"))
    g.add_argument("--section", metavar="SUITE_DIR")
    ap.add_argument("--make-run", nargs=2, metavar=("TISSUEBENCH", "SCENE"),
                    help="with --self-test: first run SCENE for --duration seconds into RUN_DIR")
    ap.add_argument("--duration", type=float, default=1.0)
    a = ap.parse_args(argv)
    if a.self_test:
        if a.make_run:
            cmd = [a.make_run[0], "leg", a.make_run[1], "--out", a.self_test, "--duration", str(a.duration),
                   "--obj-every", "0", "--quiet"]
            rc = subprocess.run(cmd, stdout=subprocess.DEVNULL).returncode
            if rc not in (0, 3):   # 3: the run blew up, which still leaves its frames to render
                print("FAIL: %s exited %d" % (" ".join(cmd), rc))
                return 1
        return self_test(a.self_test)
    if a.write_pngs:
        return write_pngs(*a.write_pngs)
    t0 = time.time()
    scenes = leg_section(a.section, load_json(os.path.join(a.section, "suite.json")))
    for s in scenes:
        for t in s["timings"]:
            print("%-28s curves %.1f s, filmstrip %.1f s, pendulum %.1f s" % (t["run"], t["curves"], t["filmstrip"],
                                                                            t["pendulum"]))
    print("leg section: %d scene(s) in %.1f s" % (len(scenes), time.time() - t0))
    return 0


if __name__ == "__main__":
    sys.exit(main())
