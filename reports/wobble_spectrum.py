#!/usr/bin/python3
"""The wobble probe's spectrum after the stop: the peaks of each axis.

leg::wobble_metrics (leg/src/analysis.cpp) reads one frequency and one damping
ratio from the probe's ring. When the flesh rings in several modes at once,
that frequency is a blend of them (a crossing rate), and a change of the
modes' shares can move it the other way from every mode. This script shows
the modes themselves.

Usage:
  /usr/bin/python3 reports/wobble_spectrum.py RUN_DIR [RUN_DIR ...] [--after S] [--peaks N]
                   [--acceleration] [--skin-box XLO YLO ZLO XHI YHI ZHI]
  /usr/bin/python3 reports/wobble_spectrum.py --self-test

RUN_DIR holds a leg run's leg.csv with probe_x, probe_y, probe_z (the
displacement of the probe's flesh from where the femur carries it, m) - a
scene with analysis.wobble, such as msd/data/physiological/wobble.yaml (one
folder per variant: RUN/relaxed, RUN/active). --after is the stop (default:
the scene's analysis.wobble.after, from the scene file that RUN_DIR's
summary.json or its parent's names, else 2.25 s).

Method, per axis, from `after` to the record's end: the signal less its
quadratic fit (the slow creep; leg::wobble_metrics uses a 0.5 s moving mean
instead), times a Hann window, zero-padded to four times its length, its FFT
magnitude; the N largest local maxima above 1 Hz are printed with their
magnitude relative to the axis' largest, and the axis' RMS. Peaks closer than
about twice the record's frequency resolution (2 / its length with the Hann
window: 0.7 Hz for 2.75 s) are not resolved from each other.

--acceleration takes the spectrum of the probe's acceleration in place of
its displacement (each peak weighted by (2 pi f)^2): what a skin-mounted
accelerometer records (Wakeling & Nigg 2001 measured the thigh's soft-tissue
vibration so; a Myoton records the tapped skin's acceleration too), where a
small ring at a high frequency can lead a large slow one.

--skin-box reads the run's leg.h5 (fields/skin_*) and, for every skin vertex
inside the box (m, the scene's frame at rest), takes the largest peak of its
acceleration's spectrum over the three axes: one accelerometer taped on the
skin there, where the probe is a mean over a region of flesh. It prints the
vertices' count and the median and quartiles of their peak frequencies. The
skin's displacement is the world frame's: use it where the femur does not
move (the wobble scenes' seated thigh).

Bad input (a folder without leg.csv or without the probe's columns, too
short a record, a bad option): a message naming it, exit 2.
"""
import argparse
import json
import os
import sys

import numpy as np


def spectrum(t, x, least_hz=1.0, acceleration=False):
    """(f, magnitude, x less its quadratic fit) of x(t), t evenly spaced, above least_hz: x less its
    quadratic fit (the slow creep), times a Hann window, zero-padded to four times its length, the FFT's
    magnitude (acceleration: of x's second derivative, the magnitude weighted by (2 pi f)^2)."""
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    s = t - t[0]
    x = x - np.polyval(np.polyfit(s, x, 2), s)
    n = 4 * len(x)
    mag = np.abs(np.fft.rfft(x * np.hanning(len(x)), n))
    f = np.fft.rfftfreq(n, s[1] - s[0])
    if acceleration:
        mag = mag * (2 * np.pi * f) ** 2
    keep = f > least_hz
    return f[keep], mag[keep], x


def peaks(t, x, count=4, least_hz=1.0, acceleration=False):
    """The `count` largest spectral peaks (Hz, relative magnitude) of x(t), t evenly spaced
    (acceleration: of x's second derivative), and the RMS of x less its quadratic fit."""
    f, mag, x = spectrum(t, x, least_hz, acceleration)
    local = [i for i in range(1, len(mag) - 1) if mag[i] >= mag[i - 1] and mag[i] >= mag[i + 1]]
    local.sort(key=lambda i: -mag[i])
    top = mag[local[0]] if local else 1.0
    return [(float(f[i]), float(mag[i] / top)) for i in local[:count]], float(np.std(x))


def stop_time(run_dir, default=2.25):
    """(analysis.wobble.after, the scene file it came from) for the scene the run's summary.json names
    (a variant's folder: its parent's); (default, None) when it cannot be read."""
    for path in (os.path.join(run_dir, "summary.json"), os.path.join(os.path.dirname(os.path.abspath(run_dir)), "summary.json")):
        try:
            with open(path) as fh:
                summary = json.load(fh)
            variants = list(summary.get("variants", {}).values())
            entry = summary if summary.get("scene_file") else (variants[0] if variants else {})
            scene_file = entry.get("scene_file")
            for o in entry.get("scene_overrides", []):  # tissuebench leg --set analysis.wobble.after=...
                if o.startswith("analysis.wobble.after="):
                    return float(o.split("=", 1)[1]), scene_file + " as changed by --set " + o
            import yaml  # Debian's python3-yaml, beside numpy

            with open(scene_file) as fh:
                return float(yaml.safe_load(fh)["analysis"]["wobble"]["after"]), scene_file
        except (OSError, KeyError, TypeError, ValueError, IndexError, ImportError, AttributeError):
            continue
    return default, None


def fail(message):
    print("wobble_spectrum: error: " + message, file=sys.stderr)
    sys.exit(2)


def read_probe(run_dir):
    path = os.path.join(run_dir, "leg.csv")
    if not os.path.isfile(path):
        fail("%s: no such file (give a leg run's folder; with variants, DIR/VARIANT)" % path)
    d = np.genfromtxt(path, delimiter=",", names=True)
    for name in ("time", "probe_x", "probe_y", "probe_z"):
        if d.dtype.names is None or name not in d.dtype.names:
            fail("%s has no column %s (a scene without analysis.wobble?)" % (path, name))
    return d


def skin_peaks(path, box, after):
    """Per skin vertex inside box (xlo, ylo, zlo, xhi, yhi, zhi), the frequency of the largest peak
    of its acceleration's spectrum over the three axes, from `after` on."""
    try:
        import h5py  # Debian's python3-h5py, beside numpy
    except ImportError:
        fail("--skin-box needs h5py (run /usr/bin/python3, Debian's python3-h5py)")
    if not os.path.isfile(path):
        fail("%s: no such file (--skin-box reads the run's leg.h5)" % path)
    try:
        with h5py.File(path, "r") as h5:
            points = h5["fields/skin_points"][:]
            t = h5["fields/skin_time"][:]
            lo, hi = np.asarray(box[:3]), np.asarray(box[3:])
            inside = np.where(np.all((points >= lo) & (points <= hi), axis=1))[0]
            if len(inside) == 0:
                fail("%s: no skin vertex inside --skin-box %s" % (path, " ".join("%g" % v for v in box)))
            d = h5["fields/skin_displacement"][:, inside, :]
    except KeyError as e:
        fail("%s has no %s (a run without the skin's fields?)" % (path, e))
    except OSError as e:
        fail("%s: not readable as HDF5 (%s)" % (path, e))
    m = t >= after
    if m.sum() < 64:
        fail("%s: fewer than 64 skin frames after %.3f s" % (path, after))
    found = [max((largest_peak(t[m], d[m, j, axis]) for axis in range(3)), key=lambda p: p[1])[0] for j in range(d.shape[1])]
    return np.asarray(found)


def largest_peak(t, x, least_hz=1.0):
    """(Hz, magnitude) of the largest value above least_hz of x's acceleration spectrum (spectrum()),
    unnormalised so that axes compare."""
    f, mag, _ = spectrum(t, x, least_hz, acceleration=True)
    i = int(np.argmax(mag))
    return float(f[i]), float(mag[i])


def report(run_dir, after, count, acceleration=False, skin_box=None):
    d = read_probe(run_dir)
    source = "--after"
    if after is None:
        after, scene = stop_time(run_dir)
        source = "analysis.wobble.after of " + scene if scene else "the default: the scene could not be read"
    m = d["time"] >= after
    if m.sum() < 64:
        fail("%s: fewer than 64 samples after %.3f s" % (run_dir, after))
    skin = skin_peaks(os.path.join(run_dir, "leg.h5"), skin_box, after) if skin_box is not None else None  # read before printing
    what = "the probe's acceleration" if acceleration else "the probe's displacement"
    print("%s (after %.3f s, %s; %.2f s of record; %s):" % (run_dir, after, source, d["time"][m][-1] - after, what))
    for axis in "xyz":
        top, rms = peaks(d["time"][m], d["probe_" + axis][m], count, acceleration=acceleration)
        print("  %s: %s   rms %.3g mm" % (axis, ", ".join("%.1f Hz (%.2f)" % p for p in top), 1e3 * rms))
    if skin is not None:
        q1, q2, q3 = np.percentile(skin, [25, 50, 75])
        print("  skin in the box (%d vertices), each one's acceleration peak: median %.1f Hz, quartiles %.1f-%.1f Hz, range %.1f-%.1f Hz"
              % (len(skin), q2, q1, q3, skin.min(), skin.max()))


def self_test():
    # Two modes, 2.0 Hz (0.5 mm, zeta 0.03) and 5.0 Hz (4 mm, zeta 0.05), under a
    # slow quadratic creep, 250 Hz for 2.75 s: both found within the resolution.
    t = np.arange(0.0, 2.75, 0.004)
    ring = lambda a, f, z: a * np.exp(-z * 2 * np.pi * f * t) * np.cos(2 * np.pi * f * np.sqrt(1 - z * z) * t)
    x = ring(0.5e-3, 2.0, 0.03) + ring(4e-3, 5.0, 0.05) + 2e-4 * t * t
    top, _ = peaks(t, x, 2)
    found = sorted(p[0] for p in top)
    assert abs(found[0] - 2.0) < 0.2 and abs(found[1] - 5.0) < 0.2, found
    assert abs(top[0][0] - 5.0) < 0.2 and top[1][1] < 1.0, top  # the larger mode first
    # One mode only: its peak leads by far.
    top, _ = peaks(t, ring(1e-3, 7.0, 0.02), 2)
    assert abs(top[0][0] - 7.0) < 0.2 and top[1][1] < 0.2, top
    # A large slow mode and a small fast one, decaying at the same rate (zeta 2 pi f the same, so
    # their peaks' heights go as their amplitudes): the displacement's spectrum leads with the
    # slow one (4 mm at 2 Hz against 1 mm at 5 Hz), the acceleration's with the fast one
    # (1 mm x (2 pi 5 Hz)^2 against 4 mm x (2 pi 2 Hz)^2: 25 against 16).
    both = ring(4e-3, 2.0, 0.03) + ring(1e-3, 5.0, 0.012)
    assert abs(peaks(t, both, 2)[0][0][0] - 2.0) < 0.2
    top, _ = peaks(t, both, 2, acceleration=True)
    assert abs(top[0][0] - 5.0) < 0.2 and abs(top[1][0] - 2.0) < 0.2 and abs(top[1][1] - 16 / 25) < 0.15, top
    # The skin box: a synthetic leg.h5 with three vertices, two in the box ringing at 9 Hz
    # (along y) and 4 Hz (along z), one outside at 20 Hz: the box's peaks are 4 and 9 Hz.
    skin = "skipped (no h5py)"
    try:
        import h5py
    except ImportError:
        h5py = None
    if h5py is not None:
        import tempfile

        with tempfile.TemporaryDirectory() as tmp:
            tt = np.arange(0.0, 3.0, 0.004)
            disp = np.zeros((len(tt), 3, 3))
            after = 0.25
            r = lambda a, f: np.where(tt >= after, a * np.sin(2 * np.pi * f * (tt - after)) * np.exp(-(tt - after)), 0.0)
            disp[:, 0, 1] = r(1e-3, 9.0)
            disp[:, 1, 2] = r(2e-3, 4.0) + 1e-4 * r(1.0, 1.5)
            disp[:, 2, 0] = r(1e-3, 20.0)
            with h5py.File(os.path.join(tmp, "leg.h5"), "w") as h5:
                h5["fields/skin_points"] = np.array([[0.0, 0.0, 0.7], [0.05, 0.0, 0.75], [0.0, 0.0, 0.2]])
                h5["fields/skin_time"] = tt
                h5["fields/skin_displacement"] = disp
            f = sorted(skin_peaks(os.path.join(tmp, "leg.h5"), [-0.1, -0.1, 0.6, 0.1, 0.1, 0.8], after))
            assert len(f) == 2 and abs(f[0] - 4.0) < 0.3 and abs(f[1] - 9.0) < 0.3, f
            skin = "the skin box's vertices at %.2f and %.2f Hz from 4 and 9 Hz" % tuple(f)
    print("wobble_spectrum self-test: passed (two modes %.2f and %.2f Hz from 2 and 5 Hz; the acceleration leads with %.2f Hz; %s)"
          % (found[0], found[1], top[0][0], skin))


def main(argv):
    if argv[1:] == ["--self-test"]:
        self_test()
        return
    parser = argparse.ArgumentParser(prog="wobble_spectrum.py", description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="+", metavar="RUN_DIR", help="a leg run's folder (with variants: DIR/VARIANT)")
    parser.add_argument("--after", type=float, help="the stop, s (default: the scene's analysis.wobble.after)")
    parser.add_argument("--peaks", type=int, default=4, help="peaks per axis (default 4)")
    parser.add_argument("--acceleration", action="store_true", help="the spectrum of the probe's acceleration (what a skin accelerometer records)")
    parser.add_argument("--skin-box", type=float, nargs=6, metavar=("XLO", "YLO", "ZLO", "XHI", "YHI", "ZHI"),
                        help="also each skin vertex inside this box (m): its acceleration's largest peak (reads leg.h5)")
    a = parser.parse_args(argv[1:])  # a bad option: usage and exit 2
    if a.peaks < 1:
        parser.error("--peaks must be at least 1")
    if a.after is not None and not np.isfinite(a.after):
        parser.error("--after must be a finite number of seconds")
    if a.skin_box is not None and not (np.all(np.isfinite(a.skin_box)) and all(a.skin_box[i] < a.skin_box[i + 3] for i in range(3))):
        parser.error("--skin-box takes XLO YLO ZLO XHI YHI ZHI, finite, each low below its high")
    for run_dir in a.runs:
        report(run_dir, a.after, a.peaks, a.acceleration, a.skin_box)


if __name__ == "__main__":
    main(sys.argv)
