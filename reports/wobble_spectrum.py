#!/usr/bin/python3
"""The wobble probe's spectrum after the stop: the peaks of each axis.

leg::wobble_metrics (leg/src/analysis.cpp) reads one frequency and one damping
ratio from the probe's ring. When the flesh rings in several modes at once,
that frequency is a blend of them (a crossing rate), and a change of the
modes' shares can move it the other way from every mode. This script shows
the modes themselves.

Usage:
  /usr/bin/python3 reports/wobble_spectrum.py RUN_DIR [RUN_DIR ...] [--after S] [--peaks N]
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

Bad input (a folder without leg.csv or without the probe's columns, too
short a record, a bad option): a message naming it, exit 2.
"""
import argparse
import json
import os
import sys

import numpy as np


def peaks(t, x, count=4, least_hz=1.0):
    """The `count` largest spectral peaks (Hz, relative magnitude) of x(t), t evenly spaced."""
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    s = t - t[0]
    x = x - np.polyval(np.polyfit(s, x, 2), s)
    n = 4 * len(x)
    mag = np.abs(np.fft.rfft(x * np.hanning(len(x)), n))
    f = np.fft.rfftfreq(n, s[1] - s[0])
    keep = f > least_hz
    f, mag = f[keep], mag[keep]
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


def report(run_dir, after, count):
    d = read_probe(run_dir)
    source = "--after"
    if after is None:
        after, scene = stop_time(run_dir)
        source = "analysis.wobble.after of " + scene if scene else "the default: the scene could not be read"
    m = d["time"] >= after
    if m.sum() < 64:
        fail("%s: fewer than 64 samples after %.3f s" % (run_dir, after))
    print("%s (after %.3f s, %s; %.2f s of record):" % (run_dir, after, source, d["time"][m][-1] - after))
    for axis in "xyz":
        top, rms = peaks(d["time"][m], d["probe_" + axis][m], count)
        print("  %s: %s   rms %.3g mm" % (axis, ", ".join("%.1f Hz (%.2f)" % p for p in top), 1e3 * rms))


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
    print("wobble_spectrum self-test: passed (two modes %.2f and %.2f Hz from 2 and 5 Hz)" % tuple(found))


def main(argv):
    if argv[1:] == ["--self-test"]:
        self_test()
        return
    parser = argparse.ArgumentParser(prog="wobble_spectrum.py", description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="+", metavar="RUN_DIR", help="a leg run's folder (with variants: DIR/VARIANT)")
    parser.add_argument("--after", type=float, help="the stop, s (default: the scene's analysis.wobble.after)")
    parser.add_argument("--peaks", type=int, default=4, help="peaks per axis (default 4)")
    a = parser.parse_args(argv[1:])  # a bad option: usage and exit 2
    if a.peaks < 1:
        parser.error("--peaks must be at least 1")
    if a.after is not None and not np.isfinite(a.after):
        parser.error("--after must be a finite number of seconds")
    for run_dir in a.runs:
        report(run_dir, a.after, a.peaks)


if __name__ == "__main__":
    main(sys.argv)
