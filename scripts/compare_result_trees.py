#!/usr/bin/env python3
"""Compare every results file (*.h5) under folder A with its namesake under folder B,
dataset by dataset (/series, /fields, /metrics, ...): exact equality, or for each
differing dataset max |A - B| over the larger of max |A| and max |B|.

  /usr/bin/python3 scripts/compare_result_trees.py A B [SKIP,...]

SKIP: comma-separated substrings of dataset paths to leave out (e.g. timing).
Used to show that a refactor leaves results bit-identical (issue 15); h5diff is
not used because it reported "0 differences" on files that differ."""
import sys, os, h5py, numpy as np
a_root, b_root = sys.argv[1], sys.argv[2]
skip = tuple(sys.argv[3].split(',')) if len(sys.argv) > 3 else ()
def datasets(f):
    out = {}
    f.visititems(lambda n, o: out.__setitem__(n, o) if isinstance(o, h5py.Dataset) else None)
    return out
n_same = n_diff = 0
for dp, _, files in os.walk(a_root):
    for fn in sorted(files):
        if not fn.endswith('.h5'): continue
        pa = os.path.join(dp, fn); rel = os.path.relpath(pa, a_root); pb = os.path.join(b_root, rel)
        if not os.path.exists(pb): print(f"MISSING in B: {rel}"); n_diff += 1; continue
        with h5py.File(pa, 'r') as fa, h5py.File(pb, 'r') as fb:
            da, db = datasets(fa), datasets(fb)
            diffs = []
            for k in sorted(set(da) | set(db)):
                if any(s in k for s in skip): continue
                if k not in da or k not in db: diffs.append(f"{k}: only in {'A' if k in da else 'B'}"); continue
                x, y = da[k][()], db[k][()]
                if x.dtype.kind in 'fiu' and y.dtype.kind in 'fiu':
                    if x.shape != y.shape: diffs.append(f"{k}: shape {x.shape} vs {y.shape}"); continue
                    xf, yf = np.asarray(x, float), np.asarray(y, float)
                    same = np.array_equal(xf, yf, equal_nan=True)
                    if not same:
                        d = np.abs(xf - yf); s = max(np.nanmax(np.abs(xf)), np.nanmax(np.abs(yf)), 1e-300)
                        r = np.nanmax(d) / s
                        diffs.append(f"{k}: max diff / max |value| {r:.3g}")
                else:
                    if not np.array_equal(np.asarray(x), np.asarray(y)): diffs.append(f"{k}: differs (non-numeric)")
            if diffs: n_diff += 1; print(f"DIFF {rel}\n  " + "\n  ".join(diffs))
            else: n_same += 1; print(f"same {rel} ({len(da)} datasets)")
print(f"{n_same} files identical, {n_diff} differ")
