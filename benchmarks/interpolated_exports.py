"""The same loops sampled and exported interpolated from a swinging-door historian.

A compressing historian stores a point only when a signal leaves a band (the deviation)
around the line from the last stored point; an interpolated export (PI's) draws straight
lines between the stored points. The pretrained model judges each set of loops twice,
paired: as sampled, and with PV and OP so exported. Sets:

- the default world of ``make_loops`` (300 loops of 3,000 samples, draw 11) and the second
  simulator (``independent_world.py``, 300 loops of 6,000 s, draw 2030), each channel
  compressed with a deviation log-uniform between 0.3 % and 5 % of its 1-99 % range;
- the third simulator (``third_world.py``), draws 0 and 1 of 300 loops, recorded sampled
  and swinging-door interpolated from the same draws (its own deviations: 0.03-0.5 % of
  span per tag, a stored point at least every 1-8 h).

Printed per set and recording: balanced accuracy ("no verdict" counts as no stiction),
recall, specificity, the share without a verdict, and the share of loops whose verdict is
the same on both recordings. An export that reads like its sampled record gets the same
verdict; the noise level read from the stored points (``noise_std``) is what lets it.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/interpolated_exports.py`` (about 4 min).
"""

from __future__ import annotations

import time

import numpy as np
from independent_world import make_independent_loops
from third_world import _swinging_door
from third_world import make as make_third

from sktiction import pretrained_classifier
from sktiction.datasets import make_loops


def interpolated(v, dev):
    """``v`` (NaN-padded) exported interpolated from a swinging door of deviation ``dev``."""
    ok = np.isfinite(v)
    x = v[ok]
    t = np.arange(x.size, dtype=float)
    keep = np.flatnonzero(_swinging_door(t, x, dev, np.inf))
    out = v.copy()
    out[ok] = np.interp(t, keep, x[keep])
    return out


def exported(X, random_state):
    rng = np.random.default_rng(random_state)
    out = X.copy()
    for i in range(len(X)):
        for c in (0, 1):
            lo, hi = np.nanpercentile(X[i, :, c], [1, 99])
            share = np.exp(rng.uniform(np.log(0.003), np.log(0.05)))
            out[i, :, c] = interpolated(X[i, :, c], share * max(hi - lo, 1e-12))
    return out


def judged(clf, X, y):
    report = clf.diagnose(X)
    pred = report["prediction"].fillna(0).to_numpy(dtype=int)
    recall, specificity = pred[y == 1].mean(), 1 - pred[y == 0].mean()
    scores = (0.5 * (recall + specificity), recall, specificity, (~report["in_domain"]).mean())
    return pred, scores


def main():
    t0 = time.perf_counter()
    clf = pretrained_classifier()
    pairs = []
    X, y = make_loops(300, n_samples=3000, random_state=11)
    pairs.append(("default world", X, exported(X, 5), y))
    X, y, _ = make_independent_loops(300, 6000, random_state=2030)
    pairs.append(("second simulator", X, exported(X, 5), y))
    for seed in (0, 1):
        X, y, _ = make_third(300, random_state=seed, fixed={"recording": "sampled"})
        E, _, _ = make_third(300, random_state=seed, fixed={"recording": "sdc_interp"})
        pairs.append((f"third simulator {seed}", X, E, y))
    print(f"{'set':18s} {'recording':12s} {'balanced':>8s} {'recall':>7s} {'spec':>6s} "
          f"{'no verdict':>10s} {'same verdict':>12s}")  # fmt: skip
    for name, sampled, export, y in pairs:
        a, sa = judged(clf, sampled, y)
        b, sb = judged(clf, export, y)
        for rec, s, same in (("sampled", sa, ""), ("interpolated", sb, f"{np.mean(a == b):.3f}")):
            print(f"{name:18s} {rec:12s} {s[0]:8.3f} {s[1]:7.3f} {s[2]:6.3f} {s[3]:10.3f} "
                  f"{same:>12s}", flush=True)  # fmt: skip
    print(f"({time.perf_counter() - t0:.0f} s)")


if __name__ == "__main__":
    main()
