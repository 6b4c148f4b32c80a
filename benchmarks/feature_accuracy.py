"""The figures behind the feature tests, printed: shapes, oscillation detection, Eq. 12.

Run: python benchmarks/feature_accuracy.py
"""

import sys
from pathlib import Path

import numpy as np

from sktiction.cycles import analyze_cycles
from sktiction.features.templates import SHAPES, make_shape_cycles, match_cycles

sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))
from test_area_ratio import eq12, lag_response, loop_r, rectangular_wave  # noqa: E402
from test_cycles import STRETCH, intermittent  # noqa: E402

print("shape matching (20 cycles x 10 seeds per shape; halves up to 2x, amplitudes up to 50 %, "
      "period +-30 %):")
for snr in (20.0, 10.0):
    rates = []
    for k, shape in enumerate(SHAPES):
        hits = [np.mean(match_cycles(*make_shape_cycles(shape, 20, snr_db=snr,
                                                        random_state=s)).argmin(1) == k)
                for s in range(10)]
        rates.append(np.mean(hits))
    per = ", ".join(f"{s} {r:.3f}" for s, r in zip(SHAPES, rates))
    print(f"  {snr:.0f} dB: all {np.mean(rates):.3f} ({per})")

white = sum(analyze_cycles(np.random.default_rng(s).normal(size=2000)).oscillating
            for s in range(200))
walks = sum(analyze_cycles(np.cumsum(np.random.default_rng(s).normal(size=2000))).oscillating
            for s in range(200))
print(f"called oscillating: white noise {white}/200, random walks {walks}/200")

overlaps, count_err = [], []
for seed in range(20):
    x, on, period = intermittent(seed)
    a = analyze_cycles(x)
    found = np.zeros(x.size, bool)
    for s, e in a.segments:
        found[s:e] = True
    overlaps.append((found & on).sum() / (found | on).sum())
    mids = a.crossings[a.cycles][:, [0, 2]].mean(axis=1)
    counts = np.histogram(mids, bins=np.arange(5) * STRETCH)[0]
    whole = np.array([0, 1, 0, 1]) * np.floor(STRETCH / period)  # whole cycles that fit
    count_err.append(np.abs(counts - whole).max())
print(f"intermittent oscillation, 20 seeds: overlap min {min(overlaps):.3f} median "
      f"{np.median(overlaps):.3f}; worst error in the cycle count of a stretch (against the "
      f"whole cycles that fit in it) {max(count_err):.0f}")

print("Eq. 12, rectangular wave into a first-order lag (R measured / Eq. 12):")
for b in (0.5, 1, 2, 4, 7, 10):
    ts = b / 200
    y = lag_response(rectangular_wave(b, ts), ts, 1.0)
    print(f"  b/T = {b:4.1f}: R = {loop_r(-y[y.size // 4:]):7.3f}, Eq. 12 = {eq12(b):7.3f}")
